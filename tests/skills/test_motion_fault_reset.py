"""Motion resets a drive fault the base offers to reset (`--reset-faults`) only while no goal asks
for motion, and the robot then stands until a goal commands anew (issue 24 point 3). HOROS's
P2OS base on its emulator, in lock-step."""
from __future__ import annotations

import math

from skills.motion import Goal
from skills.skillset import open_skills


def ticks(skills, n: int) -> list[dict]:
    clock, events = skills.hardware.clock, []
    for _ in range(n):
        skills.sense()
        skills.act()
        clock.advance(0.1)
        events += [e.as_dict() for e in skills.events.drain()]
    return events


def test_a_fault_is_reset_only_once_no_goal_asks_for_motion():
    skills = open_skills("horos", fast=True, seed=1, reset_faults=True)
    base = skills.hardware.base
    world = skills.hardware.simulation.world
    try:
        ticks(skills, 5)
        skills.motion.start(Goal("turn_to", bearing=world.body.th + math.pi), skills.now())
        ticks(skills, 5)
        assert abs(world.body.w) > 0.1                       # turning
        base.emulator.press_estop()
        ticks(skills, 5)
        base.emulator.press_estop(False)
        events = ticks(skills, 20)                          # the goal still asks for motion
        assert base.drive_fault is not None and world.body.w == 0.0
        assert not [e for e in events if e["kind"] == "fault_reset"]
        skills.motion.cancel(skills.now())                  # the application stands still
        events = ticks(skills, 10)
        resets = [e for e in events if e["kind"] == "fault_reset"]
        assert len(resets) == 1 and resets[0]["sent"] and resets[0]["device"] == "P2OS motors"
        assert base.drive_fault is None and skills.blackboard.value("robot/link")
        assert world.body.w == 0.0 and world.body.v == 0.0  # still, until commanded anew
        skills.motion.start(Goal("turn_to", bearing=world.body.th + math.pi), skills.now())
        ticks(skills, 5)
        assert abs(world.body.w) > 0.1
    finally:
        skills.close()
