"""A behavior that raises stops the robot, and nothing resumes motion by itself."""
from __future__ import annotations

import py_trees
import pytest

import behaviors.active as active_module
from behaviors.exceptions import BehaviorFault
from behaviors.registry import BehaviorSpec, Realization
from behaviors.robot import open_robot
from skills.motion import Goal


class Boom(py_trees.behaviour.Behaviour):
    def __init__(self, ctx):
        super().__init__("Boom")
        self.ctx, self.ticks = ctx, 0

    def initialise(self):
        self.ctx.skills.motion.start(Goal("turn_to", bearing=3.0), self.ctx.skills.now())

    def update(self):
        self.ticks += 1
        if self.ticks > 3:
            raise RuntimeError("sensor driver returned garbage")
        return py_trees.common.Status.RUNNING


def test_a_raising_behavior_stops_the_robot_for_good(monkeypatch):
    boom = BehaviorSpec("Boom", "raises", (Realization("default", frozenset(), Boom),))
    monkeypatch.setattr(active_module, "get_behavior", lambda name: boom)
    robot = open_robot("perses", fast=True)
    try:
        robot.activate("Boom")
        turning = []
        for _ in range(12):
            robot.sense()
            robot.act()
            turning.append(robot.skills.blackboard.value("motion/command"))
            robot.wait_until(robot.now() + 0.1)
        assert any(w != 0.0 for _, w in turning[:3]), "the behavior did turn the robot at first"
        assert robot.fault and "sensor driver returned garbage" in robot.fault
        assert all(cmd == (0.0, 0.0) for cmd in turning[4:])
        assert robot.skills.hardware.simulation.world.body.w == pytest.approx(0.0, abs=1e-6)
        assert any(e["kind"] == "fault" for e in robot.events())
        with pytest.raises(BehaviorFault):
            robot.activate("Boom")
    finally:
        robot.close()
