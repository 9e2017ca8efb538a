"""Localization: the robot's pose and velocity from base odometry, and whether the link is fresh.

A pose older than `STALE_AFTER` seconds, or a base that reports its link down, makes
`robot/link` false; the safety arbiter then refuses to move.
"""
from __future__ import annotations

from robots.base import Base, BaseState
from skills.skill import Skill
from skills.status import RUNNING, failed


class Localization(Skill):
    name = "localization"
    STALE_AFTER = 0.5    # s: five missed 10 Hz cycles

    def __init__(self, blackboard, events, base: Base) -> None:
        super().__init__(blackboard, events)
        self.base = base
        self.state: BaseState | None = None

    def sense(self, now: float) -> None:
        state = self.base.read_state()
        self.state = state
        fresh = state.link_up and now - state.t <= self.STALE_AFTER
        self.write("robot/pose", (state.x, state.y, state.th), state.t)
        self.write("robot/velocity", (state.v, state.w), state.t)
        self.write("robot/link", fresh, now)
        self.set_status(RUNNING if fresh else failed(self._why_stale(state, now)), now)

    @staticmethod
    def _why_stale(state: BaseState, now: float) -> str:
        if not state.link_up:
            return "base link is down"
        return f"base state is {now - state.t:.2f} s old"
