"""Narrow doors on a user's map: each bundled robot turns from a 1.0 m hallway through a 0.8 m
door into a room, and drives straight through a door 0.25 m wider than its footprint (HOROS's
rectangle is 0.393 m wide, PERSES's circle 0.52 m, ARGOS's 0.56 m), and arrives slowly, never
touching a wall and never "blocked" by the empty opening (issue 22, point 2: the controller's
clearance term made standing before such a door the best command; a path cut past the jamb, a
sonar echo of the jamb put on its cone's axis and the safety arbiter's fixed stop distance
each stopped a robot there)."""
from __future__ import annotations

import numpy as np
import pytest

from skills.skillset import open_skills
from tests.drawn_maps import FREE, OCCUPIED, DrawnMap

RES = 0.05


def write_door_map(folder, door: float):
    """A 1.0 m hallway (x 0 .. 8, y 0 .. 1) with 0.2 m walls; a 3 m × 3 m room north of it
    entered by a door of `door` m centred at x = 6.0; unknown space around. The robot turns
    into the door."""
    drawn = DrawnMap(9.0, 5.0, origin=(-0.5, -0.5), resolution=RES)
    drawn.fill(-0.2, -0.2, 8.2, 4.4, OCCUPIED).fill(0.0, 0.0, 8.0, 1.0, FREE)
    drawn.fill(4.5, 1.2, 7.5, 4.2, FREE).fill(6.0 - door / 2, 1.0, 6.0 + door / 2, 1.2, FREE)
    return drawn.write(folder, "door", "  robot_home: [1.0, 0.5, 0]\n  room: [6.0, 3.0, 90]\n")


def write_cross_wall_map(folder, door: float):
    """A 2 m hallway (x 0 .. 8, y 0 .. 2) cut at x = 4.0 by a 0.2 m wall with a door of `door`
    m centred at y = 1.0: the robot drives straight through it."""
    drawn = DrawnMap(9.0, 5.0, origin=(-0.5, -0.5), resolution=RES)
    drawn.fill(-0.2, -0.2, 8.2, 2.2, OCCUPIED).fill(0.0, 0.0, 8.0, 2.0, FREE)
    drawn.fill(4.0, 0.0, 4.2, 2.0, OCCUPIED).fill(4.0, 1.0 - door / 2, 4.2, 1.0 + door / 2, FREE)
    return drawn.write(folder, "wall", "  robot_home: [1.0, 1.3, 0]\n  room: [7.0, 0.8, 0]\n")


def drive_to_room(robot, map_path):
    """Go to "room"; the phases, the navigation state and the world at the end."""
    skills = open_skills(robot, fast=True, map=map_path)
    world = skills.hardware.simulation.world
    phases, speeds = [], []
    try:
        for _ in range(10):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
        assert skills.navigation.go_to("room", skills.now()).running
        for _ in range(600):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
            state = skills.blackboard.value("navigation/state")
            phases.append(state.phase)
            speeds.append((world.body.x, world.body.y, abs(world.body.v)))
            if state.phase in ("arrived", "failed"):
                break
    finally:
        skills.close()
    return phases, state, world, np.array(speeds)


@pytest.mark.parametrize("robot", ["horos", "perses", "argos"])
def test_each_robot_turns_through_a_door_of_0_8_m_and_arrives(tmp_path, robot):
    phases, state, world, _ = drive_to_room(robot, write_door_map(tmp_path, 0.8))
    body = world.body
    assert phases[-1] == "arrived", (state.reason, len(phases), body.x, body.y, body.th)
    assert "blocked" not in phases
    assert world.measures.contact_count() == 0
    assert world.measures.min_wall_clearance > 0.0
    assert abs(body.y - 3.0) < 0.3 and abs(body.x - 6.0) < 0.3


@pytest.mark.parametrize("robot, door", [("horos", 0.65), ("perses", 0.8), ("argos", 0.85)])
def test_each_robot_drives_straight_through_a_door_0_25_m_wider_than_it_slowly_and_centred(
        tmp_path, robot, door):
    """Doors at the map's 5 cm: 0.393 + 0.25 m is 0.65, 0.52 + 0.25 m 0.8, 0.56 + 0.25 m 0.85."""
    phases, state, world, track = drive_to_room(robot, write_cross_wall_map(tmp_path, door))
    assert phases[-1] == "arrived", (state.reason, len(phases))
    assert "blocked" not in phases
    assert world.measures.contact_count() == 0 and world.measures.min_wall_clearance > 0.0
    in_door = track[(track[:, 0] > 3.9) & (track[:, 0] < 4.3)]
    assert len(in_door)
    assert np.abs(in_door[:, 1] - 1.0).max() < 0.07          # centred
    assert in_door[:, 2].max() <= 0.26                        # slowly (ControllerParams.narrow_speed)


def test_an_opening_narrower_than_the_robot_is_no_path(tmp_path):
    """ARGOS (0.56 m) and a 0.6 m door: no path for it, said at once, not "blocked" later."""
    skills = open_skills("argos", fast=True, map=write_cross_wall_map(tmp_path, 0.6))
    try:
        for _ in range(10):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
        status = skills.navigation.go_to("room", skills.now())
    finally:
        skills.close()
    assert status.failed and status.reason.startswith("no path"), status.reason
