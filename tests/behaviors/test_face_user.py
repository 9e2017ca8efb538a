"""FaceUser in the simulated world: HOROS pans its head to the person, PERSES turns its body."""
from __future__ import annotations

import math

import pytest

from behaviors.robot import open_robot


def run_face_user(robot_name: str, scenario, seconds: float = 6.0):
    robot = open_robot(robot_name, fast=True, scenario=scenario, seed=3)
    try:
        for _ in range(10):                      # let the tracker confirm the person
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        robot.activate("FaceUser", {"say": "Hello!"})
        for _ in range(int(seconds / 0.1)):
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        world = robot.skills.hardware.simulation.world
        return world.body.th, robot.skills.blackboard.value("head/pan_tilt"), robot.events()
    finally:
        robot.close()


def bearing_to_person() -> float:
    return math.atan2(0.5 - (-0.75), 2.0 - 0.0)     # from robot_home (0, -0.75)


def test_horos_turns_its_head_not_its_body(standing_person):
    heading, pan_tilt, events = run_face_user("horos", standing_person(2.0, 0.5))
    assert heading == pytest.approx(math.pi / 2, abs=math.radians(2))
    assert pan_tilt[0] == pytest.approx(bearing_to_person() - math.pi / 2, abs=math.radians(8))
    assert [e["text"] for e in events if e["kind"] == "say"] == ["Hello!"]


def test_perses_turns_its_whole_body(standing_person):
    heading, pan_tilt, _ = run_face_user("perses", standing_person(2.0, 0.5))
    assert pan_tilt is None                          # no pan-tilt head on a B21r
    assert heading == pytest.approx(bearing_to_person(), abs=math.radians(8))
