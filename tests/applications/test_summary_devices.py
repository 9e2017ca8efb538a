"""The run summary counts the link episodes of each device apart from the base's."""
from __future__ import annotations

from applications.runtime import RunSummary, _describe as describe_event


def test_device_link_episodes_are_counted_per_device():
    summary = RunSummary()
    for event in ({"t": 1.0, "kind": "link", "state": "down", "reason": "no SIP"},
                  {"t": 2.0, "kind": "link", "state": "up", "after": 1.0},
                  {"t": 3.0, "kind": "link", "device": "head", "state": "down",
                   "reason": "no valid reply for 0.70 s"},
                  {"t": 5.5, "kind": "link", "device": "head", "state": "up", "after": 2.5},
                  {"t": 6.0, "kind": "link", "device": "head", "state": "down",
                   "reason": "3 error replies in a row"}):
        summary.count(event)
    lines = summary.lines()
    assert "link to the base: down 1 time(s), re-connected 1 time(s), 1.0 s down in all" in lines
    assert ("link to the head: down 2 time(s), re-connected 1 time(s), 2.5 s down in all; "
            "down at the end") in lines
    assert summary.link_downs == 1


def test_a_device_link_event_reads_as_that_device():
    down = describe_event({"t": 3.0, "kind": "link", "device": "head", "state": "down",
                           "reason": "no valid reply"}, "horos")
    assert "HEAD LINK DOWN: no valid reply" in down and "robot is stopped" not in down
    up = describe_event({"t": 4.0, "kind": "link", "device": "head", "state": "up",
                         "after": 1.0}, "horos")
    assert "head link back up after 1.0 s" in up


def test_the_base_link_line_names_the_controller_of_the_newest_episode():
    summary = RunSummary()
    for event in ({"t": 1.0, "kind": "link", "state": "down", "reason": "no SIP for 0.36 s",
                   "base": "P2OS controller on socket://127.0.0.1:8101"},
                  {"t": 2.0, "kind": "link", "state": "up", "after": 1.0},
                  {"t": 3.0, "kind": "link", "state": "down", "base": "P2OS controller on "
                   "socket://127.0.0.1:8101", "reason": "while closing: no stop could be sent"}):
        summary.count(event)
    assert ("link to the base: down 2 time(s), re-connected 1 time(s), 1.0 s down in all; down "
            "at the end; last down: P2OS controller on socket://127.0.0.1:8101: while closing: "
            "no stop could be sent") in summary.lines()
