"""Obstacle sensing: sonar ranges (from the base) and the free distance straight ahead and behind.

The free distance counts every sonar and laser reading that falls inside the corridor the
body sweeps when driving forward (backward); the safety arbiter stops forward (backward)
motion when it is short. A robot with no sonar facing backwards reports no free space behind
(0 m): it cannot see there, so it does not back up.
"""
from __future__ import annotations

import math

import numpy as np

from robots.devices import Laser
from robots.profile import RobotProfile
from skills.localization import Localization
from skills.skill import Skill


class ObstacleSensing(Skill):
    name = "obstacles"

    def __init__(self, blackboard, events, profile: RobotProfile, localization: Localization,
                 laser: Laser | None) -> None:
        super().__init__(blackboard, events)
        self.localization = localization
        self.laser = laser
        self.half_width = profile.width / 2
        self.front = profile.length / 2 if profile.shape == "rectangle" else profile.radius
        sonar = profile.sonar
        self._sonar_poses = sonar.poses if sonar is not None else np.zeros((0, 3))
        self._sees_behind = bool(np.any(np.cos(self._sonar_poses[:, 2]) < -0.5))

    def sense(self, now: float) -> None:
        state = self.localization.state
        sonar = state.sonar if state is not None else ()
        self.write("sensors/sonar", tuple(sonar), now)
        free = self._free_ahead_sonar(sonar)
        self.write("obstacles/rear", self._free_behind_sonar(sonar), now)
        if self.laser is not None:
            scan = self.laser.read()
            if scan is not None:
                hit = np.isfinite(scan.ranges)
                # the beams' angles are in the robot frame already (the mount heading included)
                ranges, angles = scan.ranges[hit], scan.angles[hit]
                free = min(free, self._free_ahead_points(scan.origin[0] + ranges * np.cos(angles),
                                                         scan.origin[1] + ranges * np.sin(angles)))
        self.write("obstacles/front", free, now)

    def _free_behind_sonar(self, ranges) -> float:
        """The free distance behind from the sonars; 0 without any facing backwards, or
        before the first reading (unknown is not free)."""
        if not self._sees_behind or not len(ranges):
            return 0.0
        xs, ys = self._sonar_points(ranges)
        return self._free_ahead_points(-xs, -ys)

    def _free_ahead_sonar(self, ranges) -> float:
        if not len(ranges):
            return math.inf
        xs, ys = self._sonar_points(ranges)
        return self._free_ahead_points(xs, ys)

    def _sonar_points(self, ranges) -> tuple[np.ndarray, np.ndarray]:
        # Only the sonars the profile places count: a reading of any other (the driver should
        # have dropped it) has no pose to put it at.
        n = min(len(ranges), len(self._sonar_poses))
        r = np.asarray(ranges[:n], dtype=float)
        poses = self._sonar_poses[:n]
        echo = np.isfinite(r) & (r >= 0)
        r, poses = r[echo], poses[echo]
        xs = poses[:, 0] + r * np.cos(poses[:, 2])
        ys = poses[:, 1] + r * np.sin(poses[:, 2])
        return xs, ys

    def _free_ahead_points(self, xs: np.ndarray, ys: np.ndarray) -> float:
        ahead = np.isfinite(xs) & (xs > 0) & (np.abs(ys) <= self.half_width + 0.05)
        if not ahead.any():
            return math.inf
        return float(max(0.0, xs[ahead].min() - self.front))
