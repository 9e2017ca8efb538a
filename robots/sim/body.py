"""The robot's body in the simulated world: a unicycle (differential drive) with acceleration
limits and a footprint (a circle, or the oriented rectangle of a box-shaped base:
robots/sim/outline.py) that stops when it would run into a wall or a person.

The firmware-like watchdog is not here but in the base that drives the body: the body keeps
its last command, as motors do.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from robots.base import clamp_velocity
from robots.profile import Limits
from robots.sim.outline import Rectangle
from robots.sim.raycast import (nearest_of_many_segments, nearest_segment,
                                 point_segment_distances)

BUMPER_FRONT = 1
BUMPER_REAR = 2
FEW_WALLS = 32          # up to this many segments a plain loop measures them quicker than numpy
SURE_MARGIN = 1e-9      # m a lower bound of a gap keeps below it: far above either's rounding


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

    def __init__(self, x: float, y: float, th: float, limits: Limits, radius: float,
                 rectangle: Rectangle | None = None) -> None:
        self.x = float(x)
        self.y = float(y)
        self.th = float(th)
        self._circles: tuple | None = None    # (pose, circles) of the last `circles()`
        self.limits = limits
        self.radius = float(radius)        # the bounding circle people keep away from
        self.rectangle = rectangle         # the outline of a box-shaped base (None: the circle)
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
        turns = self.rectangle is not None and self.w != 0.0     # a corner sweeps round
        if ((self.v != 0.0 or turns) and obstacles is not None
                and self._blocked(x, y, obstacles, th)):
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

    def clearance(self, x: float, y: float, obstacles: Obstacles,
                  th: float | None = None) -> float:
        """Smallest gap between the footprint at (x, y[, th]) and any obstacle (negative:
        overlap)."""
        if self.rectangle is not None:
            return min(self.gap_to_walls(obstacles.segments, x, y, th),
                       self.gap_to_circles(obstacles.circles, x, y, th))
        gap = math.inf
        if len(obstacles.segments):
            gap = float(point_segment_distances(x, y, obstacles.segments).min()) - self.radius
        circles = obstacles.circles
        if len(circles):
            centre = np.hypot(circles[:, 0] - x, circles[:, 1] - y) - circles[:, 2]
            gap = min(gap, float(centre.min()) - self.radius)
        return gap

    def gap_to_walls(self, segments: np.ndarray, x: float | None = None,
                     y: float | None = None, th: float | None = None) -> float:
        """Smallest gap between the footprint (at its pose, or the one given) and wall
        segments (m, 4); inf without any."""
        x, y, th = self._pose(x, y, th)
        if not len(segments):
            return math.inf
        if self.rectangle is not None:
            return self.rectangle.gap_to_segments(x, y, th, segments)
        return float(point_segment_distances(x, y, segments).min()) - self.radius

    def gap_to_circles(self, circles: np.ndarray, x: float | None = None,
                       y: float | None = None, th: float | None = None) -> float:
        """Smallest gap between the footprint and circles (k, 3) cx, cy, r; inf without any."""
        x, y, th = self._pose(x, y, th)
        if not len(circles):
            return math.inf
        if self.rectangle is not None:
            return float(self.rectangle.gap_to_circles(x, y, th, circles).min())
        centre = np.hypot(circles[:, 0] - x, circles[:, 1] - y) - circles[:, 2]
        return float(centre.min()) - self.radius

    def gap_to_circle(self, cx: float, cy: float, r: float) -> float:
        """Gap between the footprint where it stands and one circle (a person's body)."""
        if self.rectangle is not None:
            return self.rectangle.gap_to_point(self.x, self.y, self.th, cx, cy) - r
        return math.hypot(cx - self.x, cy - self.y) - self.radius - r

    def circles(self) -> np.ndarray:
        """(k, 3) circles that make up the footprint where it stands, for the crowd, which
        keeps people out of circles: the bounding circle of a round body; a rectangle's
        filling circles (robots/sim/outline.py)."""
        pose = (self.x, self.y, self.th)      # asked for several times a substep
        if self._circles is None or self._circles[0] != pose:
            circles = (self.rectangle.circles(*pose) if self.rectangle is not None
                       else np.array([(self.x, self.y, self.radius)]))
            circles.flags.writeable = False
            self._circles = (pose, circles)
        return self._circles[1]

    def gap_bound(self, segments: np.ndarray, circles: np.ndarray | None = None,
                  x: float | None = None, y: float | None = None) -> float:
        """A lower bound of the gap between a box-shaped footprint at (x, y), at any heading,
        and segments (m, 4) and circles (k, 3): the nearest one's distance from the centre less
        the half diagonal. A few array operations where the exact outline takes dozens: it
        decides alone whenever nothing is near."""
        x, y, _ = self._pose(x, y, None)
        near = (nearest_segment(x, y, segments) if len(segments) <= FEW_WALLS
                else nearest_of_many_segments(x, y, segments))
        if circles is not None and len(circles):
            for cx, cy, radius in circles.tolist():
                near = min(near, math.hypot(cx - x, cy - y) - radius)
        return near - self.rectangle.half_diagonal - SURE_MARGIN

    def _pose(self, x, y, th) -> tuple[float, float, float]:
        return (self.x if x is None else x, self.y if y is None else y,
                self.th if th is None else th)

    def _blocked(self, x: float, y: float, obstacles: Obstacles, th: float) -> bool:
        """True when the move ends in overlap and goes deeper (backing out is always allowed).
        A box whose bound already says clear is not measured exactly (the answer is the same)."""
        if (self.rectangle is not None
                and self.gap_bound(obstacles.segments, obstacles.circles, x, y) >= 0.0):
            return False
        after = self.clearance(x, y, obstacles, th)
        if after >= 0.0:
            return False
        return after < self.clearance(self.x, self.y, obstacles, self.th)

