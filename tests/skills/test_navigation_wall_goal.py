"""A place drawn close to a wall, approached facing the wall: the safety arbiter stops forward
motion short of it, so the skill turns to the place's heading there and arrives, instead of
creeping against the veto until it gives up."""
from __future__ import annotations

import math

import pytest

from skills.skillset import open_skills

SCENARIO = '[scenario]\nname = "diagonal"\nduration = 60.0\nrobot = [{x}, {y}, {heading}]\n'


@pytest.mark.parametrize("robot", ["horos", "perses"])
def test_arrives_at_robot_home_approached_diagonally_towards_the_wall(tmp_path, robot):
    path = tmp_path / "diagonal.toml"
    path.write_text(SCENARIO.format(x=-1.4, y=0.3, heading=-35))
    skills = open_skills(robot, fast=True, scenario=str(path), seed=5)
    try:
        world = skills.hardware.simulation.world
        skills.navigation.go_to("robot_home", skills.now())
        for _ in range(300):
            skills.sense(); skills.act(); skills.hardware.clock.advance(0.1)
            if not skills.navigation.status.running:
                break
        home = skills.map.places["robot_home"]
        assert skills.navigation.status.succeeded, skills.navigation.status
        assert math.hypot(world.body.x - home[0], world.body.y - home[1]) <= 0.3
        error = math.atan2(math.sin(world.body.th - home[2]), math.cos(world.body.th - home[2]))
        assert abs(error) < math.radians(10)
        assert world.measures.contact_count() == 0
    finally:
        skills.close()
