"""The robot's body in the simulated world: a unicycle (differential drive) with acceleration
limits and a circular footprint that stops when it would run into a wall or a person.

The firmware-like watchdog is not here but in the base that drives the body: the body keeps
its last command, as motors do.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from robots.base import clamp_velocity
from robots.profile import Limits
from robots.sim.raycast import point_segment_distances

BUMPER_FRONT = 1
BUMPER_REAR = 2


@dataclass(frozen=True)
class Obstacles:
    """What the body can run into: wall segments (m, 4) and circles (k, 3) cx, cy, r."""
    segments: np.ndarray
    circles: np.ndarray


def _approach(current: float, target: float, max_change: float) -> float:
    """Move `current` towards `target` by at most `max_change`."""
    if target > current:
        return min(target, current + max_change)
    return max(target, current - max_change)


class UnicycleBody:
    """Pose (x, y, th), velocities (v, w) and the command they ramp towards."""

    def __init__(self, x: float, y: float, th: float, limits: Limits, radius: float) -> None:
        self.x = float(x)
        self.y = float(y)
        self.th = float(th)
        self.limits = limits
        self.radius = float(radius)
        self.v = 0.0
        self.w = 0.0
        self.cmd_v = 0.0
        self.cmd_w = 0.0
        self.stalled = False
        self.bumpers = 0

    def set_command(self, v: float, w: float) -> None:
        """The velocities to ramp towards, clamped to the limits (NaN becomes zero)."""
        self.cmd_v, self.cmd_w = clamp_velocity(v, w, self.limits)

    def step(self, dt: float, obstacles: Obstacles | None = None) -> None:
        """Ramp v, w within the acceleration limits and move; a blocked move stops the body."""
        if dt <= 0:
            return
        self.v = _approach(self.v, self.cmd_v, self.limits.max_accel * dt)
        self.w = _approach(self.w, self.cmd_w, self.limits.max_turn_accel * dt)
        x, y, th = self._integrate(dt)
        if self.v != 0.0 and obstacles is not None and self._blocked(x, y, obstacles):
            self.bumpers = BUMPER_FRONT if self.v > 0 else BUMPER_REAR
            self.stalled = True
            self.v = 0.0
            self.w = 0.0
            return
        self.bumpers = 0
        self.stalled = False
        self.x, self.y, self.th = x, y, th

    def _integrate(self, dt: float) -> tuple[float, float, float]:
        """Exact unicycle motion over dt at constant v, w."""
        th2 = self.th + self.w * dt
        if abs(self.w) < 1e-9:
            x = self.x + self.v * dt * math.cos(self.th)
            y = self.y + self.v * dt * math.sin(self.th)
        else:
            r = self.v / self.w
            x = self.x + r * (math.sin(th2) - math.sin(self.th))
            y = self.y - r * (math.cos(th2) - math.cos(self.th))
        th2 = (th2 + math.pi) % (2 * math.pi) - math.pi
        return x, y, th2

    def clearance(self, x: float, y: float, obstacles: Obstacles) -> float:
        """Smallest gap between the footprint at (x, y) and any obstacle (negative: overlap)."""
        gap = math.inf
        if len(obstacles.segments):
            gap = float(point_segment_distances(x, y, obstacles.segments).min()) - self.radius
        circles = obstacles.circles
        if len(circles):
            centre = np.hypot(circles[:, 0] - x, circles[:, 1] - y) - circles[:, 2]
            gap = min(gap, float(centre.min()) - self.radius)
        return gap

    def _blocked(self, x: float, y: float, obstacles: Obstacles) -> bool:
        """True when the move ends in overlap and goes deeper (backing out is always allowed)."""
        after = self.clearance(x, y, obstacles)
        if after >= 0.0:
            return False
        return after < self.clearance(self.x, self.y, obstacles)
