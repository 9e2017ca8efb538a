"""Localization turns the base's link state into trace events: one `link` down (with the
driver's reason) and one `link` up (with how long it lasted) per episode, however many ticks
it spans; and the driver's dropped readings into `dropped` events that add up to its count."""
from __future__ import annotations

from dataclasses import replace

import pytest

from robots.base import BaseState
from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.localization import Localization


class StubBase:
    def __init__(self) -> None:
        self.state = BaseState(t=0.0)

    def read_state(self) -> BaseState:
        return self.state


def ticks(localization, base, start: float, count: int, **state) -> float:
    t = start
    for _ in range(count):
        t += 0.1
        base.state = replace(base.state, t=t if state.get("link_up", True) else base.state.t,
                             **state)
        localization.sense(t)
    return t


def test_a_link_episode_is_one_down_and_one_up_event():
    base, events = StubBase(), EventLog()
    localization = Localization(Blackboard("test"), events, base)
    t = ticks(localization, base, 0.0, 5, link_up=True)
    t = ticks(localization, base, t, 20, link_up=False, extra={"link_error": "no SIP for 0.36 s"})
    ticks(localization, base, t, 5, link_up=True, extra={})
    link = [e.as_dict() for e in events.drain() if e.kind == "link"]
    assert [e["state"] for e in link] == ["down", "up"]
    assert "no SIP for 0.36 s" in link[0]["reason"]
    assert link[1]["after"] == pytest.approx(2.0, abs=0.15)


def test_dropped_readings_become_events_that_add_up_to_the_drivers_count():
    base, events = StubBase(), EventLog()
    localization = Localization(Blackboard("test"), events, base)
    t = 0.0
    for total in (0, 16, 16, 48, 64):
        t = ticks(localization, base, t, 1, extra={"dropped_readings": total,
                                                   "dropped_reason": "sonar number 20"})
    dropped = [e.as_dict() for e in events.drain() if e.kind == "dropped"]
    assert [e["count"] for e in dropped] == [16, 32, 16]
    assert dropped[-1]["total"] == 64 and dropped[-1]["reason"] == "sonar number 20"


def test_a_base_whose_first_report_comes_late_is_starting_not_down():
    """rFLEX reports a tick or two after the link opens: no fault, no link episode; but the
    link stays false (nothing moves) until the report is there."""
    base, events = StubBase(), EventLog()
    board = Blackboard("test")
    localization = Localization(board, events, base)
    t = ticks(localization, base, 0.0, 3, link_up=False, extra={"link_error": "no report yet"})
    assert localization.status.running and "first report" in localization.status.reason
    assert board.value("robot/link") is False
    ticks(localization, base, t, 5, link_up=True, extra={})
    assert [e for e in events.drain() if e.kind == "link"] == []
    assert localization.status.running and board.value("robot/link") is True


def test_a_base_that_never_reports_is_down_after_the_grace():
    base, events = StubBase(), EventLog()
    localization = Localization(Blackboard("test"), events, base)
    ticks(localization, base, 0.0, 30, link_up=False, extra={"link_error": "no report yet"})
    link = [e.as_dict() for e in events.drain() if e.kind == "link"]
    assert [e["state"] for e in link] == ["down"]
    assert link[0]["t"] == pytest.approx(0.1 + Localization.FIRST_REPORT_WITHIN, abs=0.11)
    assert localization.status.failed and "no report yet" in localization.status.reason
