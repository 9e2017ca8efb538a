"""Motion in the simulated world: approach a person to a kept distance, slowly near people."""
from __future__ import annotations

import math

from skills.motion import Goal
from skills.skillset import open_skills


def test_keep_distance_approaches_the_user_and_slows_down_near_people(standing_person):
    skills = open_skills("perses", scenario=standing_person(0.0, 0.9), fast=True, seed=5)
    clock = skills.hardware.clock
    try:
        for _ in range(10):                                   # confirm the person
            skills.sense(); skills.act(); clock.advance(0.1)
        skills.motion.start(Goal("keep_distance", distance=0.9), skills.now())
        commands, distances = [], []
        for _ in range(150):
            skills.sense(); skills.act(); clock.advance(0.1)
            commands.append(skills.blackboard.value("motion/command"))
            distances.append(skills.blackboard.value("people/user_distance"))
        limits = skills.profile.limits
        world = skills.hardware.simulation.world
        true_distance = math.hypot(world.body.x - 0.0, world.body.y - 0.9)
    finally:
        skills.close()
    assert abs(true_distance - 0.9) < 0.15
    assert skills.motion.status.succeeded
    near = [v for (v, _), d in zip(commands, distances)
            if d is not None and d < limits.near_people_distance]
    assert near and max(abs(v) for v in near) <= limits.max_speed_near_people + 1e-9
    assert max(v for v, _ in commands) > 0.0                  # it did drive towards the person
