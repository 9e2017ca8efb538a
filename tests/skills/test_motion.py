"""Motion in the simulated world: approach a person to a kept distance, slowly near people."""
from __future__ import annotations

import math

import pytest

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


def _turn_left_beside(standing_person, side: float):
    """HOROS (a box, at home facing +y) told to turn a quarter left with someone standing
    still `side` m to its left, just ahead of its axle: the box's front corner sweeps towards
    them. Returns the contacts with the robot moving, the turn made (rad) and the limits
    given."""
    # robot frame (0.12, side) in the world: the robot stands at (0, -0.75) facing +y
    scenario = standing_person(-side, -0.75 + 0.12, motion="scripted")
    skills = open_skills("horos", scenario=scenario, fast=True, seed=5)
    clock, world = skills.hardware.clock, skills.hardware.simulation.world
    try:
        for _ in range(10):                                   # the person is tracked
            skills.sense(); skills.act(); clock.advance(0.1)
        start = world.body.th
        skills.motion.start(Goal("turn_to", bearing=start + math.pi / 2), skills.now())
        limits = []
        for _ in range(60):
            skills.sense(); skills.act(); clock.advance(0.1)
            limits.append(skills.blackboard.value("motion/limit"))
        turned = math.atan2(math.sin(world.body.th - start), math.cos(world.body.th - start))
        return [c for c in world.measures.contacts if c.robot_moving], turned, limits
    finally:
        skills.close()


def test_a_box_shaped_base_does_not_sweep_its_corner_into_someone_beside_it(standing_person):
    contacts, turned, limits = _turn_left_beside(standing_person, 0.47)
    assert contacts == []
    assert 0.0 < turned < math.pi / 2 - 0.2                  # it turned, and stopped short
    assert any("sweep a corner" in why for why in limits)
    # with the person a step farther away the corner passes clear: the whole turn is made
    contacts, turned, limits = _turn_left_beside(standing_person, 0.75)
    assert contacts == [] and turned == pytest.approx(math.pi / 2, abs=0.15)
    assert not any("sweep" in why for why in limits)



def test_a_box_shaped_base_held_from_turning_backs_out_and_then_turns(standing_person):
    # HOROS in the hallway's middle facing +y, someone standing still 0.47 m to its left just
    # ahead of its axle: the turn a quarter left would sweep its front corner into them, so
    # the arbiter holds it (the test above); after WEDGED_AFTER s held, the robot backs
    # straight out until the corner clears them, then makes the whole turn, touching nobody
    from skills.wedge import BACK_OUT_MAX, WEDGED_AFTER
    scenario = standing_person(-0.47, 0.12, motion="scripted", robot=(0.0, 0.0, 90.0))
    skills = open_skills("horos", scenario=scenario, fast=True, seed=5)
    clock, world = skills.hardware.clock, skills.hardware.simulation.world
    try:
        for _ in range(10):                                   # the person is tracked
            skills.sense(); skills.act(); clock.advance(0.1)
        start, y0 = world.body.th, world.body.y
        skills.motion.start(Goal("turn_to", bearing=start + math.pi / 2), skills.now())
        limits, ys = [], []
        for _ in range(150):
            skills.sense(); skills.act(); clock.advance(0.1)
            limits.append(skills.blackboard.value("motion/limit"))
            ys.append(world.body.y)
        turned = math.atan2(math.sin(world.body.th - start), math.cos(world.body.th - start))
        contacts = [c for c in world.measures.contacts if c.robot_moving]
    finally:
        skills.close()
    assert contacts == []
    held = [k for k, why in enumerate(limits) if "sweep a corner" in why]
    backing = [k for k, why in enumerate(limits) if why.startswith("backing out")]
    assert held and backing and held[0] + WEDGED_AFTER * 10 - 1 <= backing[0]   # held first
    assert 0.05 < y0 - min(ys) <= BACK_OUT_MAX + 0.05          # backed out, not far
    assert turned == pytest.approx(math.pi / 2, abs=0.15)      # then made the whole turn
    assert skills.motion.status.succeeded
