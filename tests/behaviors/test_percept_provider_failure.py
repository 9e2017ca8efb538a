"""A percept plugin that raises while the robot runs disables its own percepts, once and for the
rest of the run; every other plugin's percepts are still read."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

import behaviors.percept_view as percept_view
from behaviors.percept_view import PerceptTracker
from behaviors.percepts import PerceptCatalog, PerceptProvider, spec
from skills.blackboard import Blackboard


def catalog_with(*providers: PerceptProvider) -> PerceptCatalog:
    specs = {s.name: s for p in providers for s in p.specs}
    return PerceptCatalog(tuple(providers), specs, {})


@pytest.fixture
def broken(monkeypatch):
    calls = {"broken": 0, "fine": 0}

    def read_broken(ctx):
        calls["broken"] += 1
        raise ZeroDivisionError("division by zero")

    def read_fine(ctx):
        calls["fine"] += 1
        return {"fine.count": 3}

    providers = (PerceptProvider("fine", (spec("fine.count", "int"),), read_fine),
                 PerceptProvider("wobbly", (spec("wobbly.near", "bool"),
                                            spec("wobbly.gap", "float", "m")), read_broken))
    monkeypatch.setattr(percept_view, "percept_catalog", lambda: catalog_with(*providers))
    return calls


def skills():
    return SimpleNamespace(blackboard=Blackboard("test"), capabilities=frozenset())


def test_a_raising_plugin_leaves_its_percepts_absent_and_disabled(broken):
    tracker = PerceptTracker()
    view = tracker.view(skills(), 1.0)
    assert view["fine.count"] == 3
    assert view["wobbly.near"] is None and view["wobbly.gap"] is None
    assert view.disabled == {"wobbly.near", "wobbly.gap"}
    [failure] = tracker.new_failures()
    assert failure.plugin == "wobbly"
    assert failure.error == "ZeroDivisionError: division by zero"
    assert failure.percepts == ("wobbly.gap", "wobbly.near")
    assert tracker.new_failures() == []          # reported once


def test_a_failed_plugin_stays_off_and_the_others_keep_being_read(broken):
    tracker = PerceptTracker()
    for t in (1.0, 1.1, 1.2):
        view = tracker.view(skills(), t)
    assert broken == {"broken": 1, "fine": 3}
    assert view.disabled == {"wobbly.near", "wobbly.gap"} and view["fine.count"] == 3


def test_a_plugin_returning_no_mapping_counts_as_failed(monkeypatch):
    provider = PerceptProvider("odd", (spec("odd.x", "int"),), lambda ctx: 42)
    monkeypatch.setattr(percept_view, "percept_catalog", lambda: catalog_with(provider))
    tracker = PerceptTracker()
    assert tracker.view(skills(), 0.0).disabled == {"odd.x"}
    assert tracker.new_failures()[0].error.startswith("TypeError")


def test_the_robot_reports_a_failed_plugin_as_a_trace_event(broken):
    from behaviors.robot import Robot
    robot = Robot.__new__(Robot)
    robot.skills = SimpleNamespace(blackboard=Blackboard("test"), capabilities=frozenset(),
                                   sense=lambda: 2.5, events=SimpleNamespace(drain=lambda: []))
    robot.percepts, robot._events = PerceptTracker(), []
    robot.active = SimpleNamespace(status=None)
    robot.sense()
    robot.sense()
    assert robot.events() == [{"t": 2.5, "kind": "plugin", "group": "percept",
                               "plugin": "wobbly", "error": "ZeroDivisionError: division by zero",
                               "percepts": ["wobbly.gap", "wobbly.near"]}]


def test_the_snapshot_marks_disabled_percepts(broken):
    from behaviors.percept_view import describe
    view = PerceptTracker().view(skills(), 1.0)
    described = describe(view, {})
    assert described["wobbly.near"]["disabled"] and "disabled" not in described["fine.count"]
