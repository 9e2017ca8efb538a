"""Localization before thick filled walls (issue 22, point 4): a SLAM map draws walls as solid
blocks with unknown space beyond; a beam ends at a wall's surface, so the likelihood falls
with the depth into the wall, and a robot standing before one is located without bias (before,
the estimate sat 15-20 cm ahead of the truth on this map)."""
from __future__ import annotations

import numpy as np
import pytest

from skills.navigation.gridmap import load_map
from skills.navigation.mcl import laser_model, likelihood_field
from skills.skillset import open_skills
from tests.drawn_maps import FREE, OCCUPIED, DrawnMap

RES = 0.05


def write_thick_walled_map(folder, wall: float = 0.6):
    """A 10 m × 2 m corridor (x 1 .. 11, y 1 .. 3) inside `wall` m filled walls, unknown
    beyond; the robot's home 3 m before the east wall, facing it."""
    drawn = DrawnMap(12.0, 6.0, resolution=RES)
    drawn.fill(1.0 - wall, 1.0 - wall, 11.0 + wall, 3.0 + wall, OCCUPIED)
    drawn.fill(1.0, 1.0, 11.0, 3.0, FREE)
    return drawn.write(folder, "thick", "  robot_home: [8.0, 2.0, 0]\n")


def test_the_likelihood_falls_with_the_depth_into_a_thick_wall_and_is_even_about_its_surface(
        tmp_path):
    grid = load_map(write_thick_walled_map(tmp_path))
    field = likelihood_field(grid, laser_model(8.0))
    row = int(2.0 / RES)                                 # across the east wall at y = 2
    surface = int(11.0 / RES)                            # first wall column
    inside = field[row, surface:surface + 6]
    assert np.all(np.diff(inside) < 0)                   # deeper is less likely
    assert field[row, surface - 1] == pytest.approx(field[row, surface])   # even about it


@pytest.mark.parametrize("robot", ["horos", "perses"])
def test_a_robot_standing_before_a_thick_wall_is_located_without_bias(tmp_path, robot):
    skills = open_skills(robot, fast=True, map=write_thick_walled_map(tmp_path), seed=1)
    world = skills.hardware.simulation.world
    errors = []
    try:
        for tick in range(200):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
            state = skills.localization.state
            if tick >= 50:
                errors.append((state.x - world.body.x, state.y - world.body.y))
    finally:
        skills.close()
    errors = np.array(errors)
    assert np.hypot(errors[:, 0], errors[:, 1]).mean() <= 0.02
    assert abs(errors[:, 0].mean()) <= 0.02
