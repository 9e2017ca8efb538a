"""Localization: the robot's pose and velocity from base odometry, and whether the link is fresh.

A pose older than `STALE_AFTER` seconds, or a base that reports its link down, makes
`robot/link` false; the safety arbiter then refuses to move, and L2's `robot.fault` percept is
true for as long as it lasts.

Why it also reports link episodes and dropped readings: a user looking at a run afterwards must
see every link-down and re-connect with its time and reason, and every reading the driver threw
away, without reading the driver's log. Events (for the trace, through `robot.events()`):
- `link` with `state` "down" and `reason`, when the base data stops being fresh;
- `link` with `state` "up" and `after` (s the episode lasted), when it is fresh again;
- `dropped` with `count` (how many since the last one), `total` and the newest `reason`, on a
  tick in which the driver dropped readings the profile does not describe.
"""
from __future__ import annotations

from robots.base import Base, BaseState
from skills.skill import Skill
from skills.status import RUNNING, failed


class Localization(Skill):
    name = "localization"
    STALE_AFTER = 0.5     # s: five missed 10 Hz cycles

    def __init__(self, blackboard, events, base: Base) -> None:
        super().__init__(blackboard, events)
        self.base = base
        self.state: BaseState | None = None
        self._fresh: bool | None = None       # None until the first tick
        self._down_since = 0.0
        self._dropped = 0

    def sense(self, now: float) -> None:
        state = self.base.read_state()
        self.state = state
        fresh = state.link_up and now - state.t <= self.STALE_AFTER
        self.write("robot/pose", (state.x, state.y, state.th), state.t)
        self.write("robot/velocity", (state.v, state.w), state.t)
        self.write("robot/link", fresh, now)
        self.set_status(RUNNING if fresh else failed(self._why_stale(state, now)), now)
        self._link_episode(fresh, state, now)
        self._dropped_readings(state, now)

    def _link_episode(self, fresh: bool, state: BaseState, now: float) -> None:
        was = self._fresh
        self._fresh = fresh
        if was is None or was == fresh:
            return
        if not fresh:
            self._down_since = now
            self.events.emit(now, "link", state="down", reason=self._why_stale(state, now))
        else:
            self.events.emit(now, "link", state="up", after=round(now - self._down_since, 3))

    def _dropped_readings(self, state: BaseState, now: float) -> None:
        count = int(state.extra.get("dropped_readings", 0) or 0)
        if count <= self._dropped:
            return
        reason = state.extra.get("dropped_reason") or "a reading the profile does not describe"
        self.events.emit(now, "dropped", count=count - self._dropped, total=count, reason=reason)
        self._dropped = count

    @staticmethod
    def _why_stale(state: BaseState, now: float) -> str:
        if not state.link_up:
            why = state.extra.get("link_error") if state.extra else None
            return f"base link is down: {why}" if why else "base link is down"
        return f"base state is {now - state.t:.2f} s old"
