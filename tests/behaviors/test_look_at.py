"""LookAt: like FaceUser, without a word (HOROS pans its head, PERSES turns its body)."""
from __future__ import annotations

import math

import pytest

from behaviors.robot import open_robot


def run_look_at(robot_name: str, scenario, seconds: float = 6.0):
    robot = open_robot(robot_name, fast=True, scenario=scenario, seed=3)
    try:
        for _ in range(10):                      # let the tracker confirm the person
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        robot.activate("LookAt", {})
        events = []
        for _ in range(int(seconds / 0.1)):
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
            events += robot.events()
        world = robot.skills.hardware.simulation.world
        return world.body.th, robot.skills.blackboard.value("head/pan_tilt"), events, world
    finally:
        robot.close()


BEARING = math.atan2(0.5 - (-0.75), 2.0 - 0.0)      # from robot_home (0, -0.75) to (2, 0.5)


def test_horos_looks_with_its_head_and_says_nothing(standing_person):
    heading, pan_tilt, events, world = run_look_at("horos", standing_person(2.0, 0.5))
    assert heading == pytest.approx(math.pi / 2, abs=math.radians(2))
    assert pan_tilt[0] == pytest.approx(BEARING - math.pi / 2, abs=math.radians(8))
    assert [e for e in events if e["kind"] == "say"] == [] and world.utterances == []


def test_perses_turns_its_whole_body(standing_person):
    heading, pan_tilt, events, _ = run_look_at("perses", standing_person(2.0, 0.5))
    assert pan_tilt is None
    assert heading == pytest.approx(BEARING, abs=math.radians(8))
    assert [e for e in events if e["kind"] == "say"] == []
