"""Narrow doors on a user's map: a robot turns from a 1.0 m hallway through a 0.8 m door into a
room and arrives, never touching a wall, and is never "blocked" by the empty opening (issue 22:
the controller's clearance term made standing before such a door the best command; PERSES
stalled there). With `ControllerParams.clearance_beyond_path`, an experiment off by default:
HOROS and PERSES pass; ARGOS does not yet."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from skills.skillset import open_skills

RES = 0.05


def write_door_map(folder, door: float):
    """A 1.0 m hallway (x 0 .. 8, y 0 .. 1) with 0.2 m walls; a 3 m × 3 m room north of it
    entered by a door of `door` m centred at x = 6.0; unknown space around."""
    def cells(metres):
        return int(round(metres / RES))
    grid = np.full((cells(5.0), cells(9.0)), 205, dtype=np.uint8)     # x -0.5 .. 8.5, y -0.5 ..

    def fill(x0, y0, x1, y1, value):
        grid[cells(y0 + 0.5):cells(y1 + 0.5), cells(x0 + 0.5):cells(x1 + 0.5)] = value
    fill(-0.2, -0.2, 8.2, 4.4, 0)
    fill(0.0, 0.0, 8.0, 1.0, 254)
    fill(4.5, 1.2, 7.5, 4.2, 254)
    fill(6.0 - door / 2, 1.0, 6.0 + door / 2, 1.2, 254)
    pixels = np.flipud(grid)
    height, width = pixels.shape
    (folder / "door.pgm").write_bytes(b"P5\n%d %d\n255\n" % (width, height) + pixels.tobytes())
    (folder / "door.yaml").write_text(
        "image: door.pgm\nresolution: 0.05\norigin: [-0.5, -0.5, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\nplaces:\n  robot_home: [1.0, 0.5, 0]\n"
        "  room: [6.0, 3.0, 90]\n")
    return folder / "door.yaml"


@pytest.mark.parametrize("robot", [
    "horos", "perses",
    pytest.param("argos", marks=pytest.mark.xfail(
        strict=True, reason="ARGOS (0.28 m radius) still stalls at the corner into the door: "
        "the planned path cuts it closer than the controller's margins allow (issue 22, "
        "point 2, open)")),
])
def test_each_robot_turns_through_a_door_of_0_8_m_and_arrives(tmp_path, robot):
    skills = open_skills(robot, fast=True, map=write_door_map(tmp_path, 0.8))
    nav = skills.navigation
    nav.params = replace(nav.params, controller=replace(nav.params.controller,
                                                        clearance_beyond_path=True))
    world = skills.hardware.simulation.world
    phases = []
    try:
        for _ in range(10):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
        assert skills.navigation.go_to("room", skills.now()).running
        for _ in range(600):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
            state = skills.blackboard.value("navigation/state")
            phases.append(state.phase)
            if state.phase in ("arrived", "failed"):
                break
    finally:
        skills.close()
    body = world.body
    assert phases[-1] == "arrived", (state.reason, len(phases), body.x, body.y, body.th)
    assert "blocked" not in phases
    assert world.measures.contact_count() == 0
    assert world.measures.min_wall_clearance > 0.0
    assert abs(world.body.y - 3.0) < 0.3 and abs(world.body.x - 6.0) < 0.3


def test_without_the_experiment_perses_stalls_before_the_door(tmp_path):
    """What the experiment changes: by default PERSES stands before the 0.8 m door."""
    skills = open_skills("perses", fast=True, map=write_door_map(tmp_path, 0.8))
    try:
        for _ in range(10):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
        skills.navigation.go_to("room", skills.now())
        for _ in range(600):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
            state = skills.blackboard.value("navigation/state")
            if state.phase in ("arrived", "failed"):
                break
    finally:
        skills.close()
    assert state.phase == "failed" and "blocked" in state.reason
