"""The terminal view (--live), progress (--progress) and the snapshot a tick observer gets."""
from __future__ import annotations

import io

import py_trees

from applications.graph.loader import find_application, load_application
from applications.live import LiveView, Progress, render, tree_lines
from applications.runtime import Run
from behaviors.percept_view import STALE_AFTER
from behaviors.robot import open_robot

SURVEY = find_application("survey")


def run_with(observers, scenario="complete", duration=50.0):
    app = load_application(SURVEY)
    robot = open_robot("horos", scenario=SURVEY / "scenarios" / f"{scenario}.toml", fast=True)
    try:
        return Run(app, robot, echo=None, duration=duration, observers=observers).run(), robot
    finally:
        robot.close()


def test_each_tick_reaches_the_observer_with_every_layers_part():
    snapshots = []
    summary, robot = run_with([snapshots.append])
    assert [s["tick"] for s in snapshots] == list(range(summary.ticks))
    fired = [s for s in snapshots if s["transition"]]
    assert [(s["transition"]["from"], s["transition"]["to"]) for s in fired] == [
        (None, "Wait"), ("Wait", "CreateAttention"), ("CreateAttention", "Interaction")]
    interaction = next(s for s in snapshots if s["state"] == "Interaction")
    robot_part = interaction["robot"]
    assert robot_part["behavior"] == "Survey"
    assert robot_part["tree"]["name"] == "Survey"
    statuses = {n["status"] for n in _nodes(robot_part["tree"])}
    assert statuses <= {s.value for s in py_trees.common.Status}
    percept = robot_part["percepts"]["user.distance"]
    assert percept["value"] is not None and 0 <= percept["age"] <= STALE_AFTER and not percept["stale"]
    skills = robot_part["skills"]
    assert skills["user"] in {t["id"] for t in skills["tracks"]}
    assert skills["blackboard"]["robot/pose"]["age"] >= 0
    assert skills["skills"]["perception"]["status"] == "running"
    hardware = skills["hardware"]
    assert hardware["truth"] and hardware["base"]["link_up"]


def _nodes(node):
    yield node
    for child in node.get("children", ()):
        yield from _nodes(child)


def test_an_observer_without_the_robot_part_gets_l3_only():
    class StateOnly:
        robot_snapshot = False

        def __init__(self):
            self.seen = []

        def __call__(self, snapshot):
            self.seen.append((snapshot["state"], snapshot["robot"]))

    observer = StateOnly()
    summary, robot = run_with([observer], duration=5.0)
    assert len(observer.seen) == summary.ticks and {r for _, r in observer.seen} == {None}
    assert robot.skills.hardware._tap is None          # nothing was tapped for it


def test_the_live_view_draws_state_behavior_tree_and_percepts():
    snapshots = []
    run_with([snapshots.append])
    snapshot = next(s for s in snapshots if s["state"] == "Interaction")
    lines = render(snapshot, ["[ 40.0] transition from=CreateAttention to=Interaction"])
    text = "\n".join(lines)
    assert "state Interaction" in text and "behavior Survey" in text
    assert tree_lines(snapshot["robot"]["tree"])[0].startswith("[*] Survey running")
    assert "user.present=True" in text and "user.distance=" in text
    stream = io.StringIO()
    view = LiveView(stream, rate=1e9)
    view(snapshot)
    assert stream.getvalue().startswith("\x1b[H\x1b[J") and "state Interaction" in stream.getvalue()


def test_progress_reports_robot_time_rate_and_states_on_its_stream():
    stream = io.StringIO()
    progress = Progress(stream, period=0.0)
    summary, _ = run_with([progress], duration=50.0)
    lines = stream.getvalue().splitlines()
    assert len(lines) == summary.ticks == progress.reports
    last = lines[-1]
    assert last.startswith("interbot: 50/50 s robot time (100%), ")
    shown = dict(part.rsplit(" ", 2)[:2] for part in last.split("ticks/s; ")[1].split(", "))
    assert set(shown) == set(summary.time_in_state)
    for state, seconds in summary.time_in_state.items():
        assert abs(float(shown[state]) - seconds) <= 1.0     # whole seconds in the line
