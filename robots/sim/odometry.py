"""Wheel odometry of the simulated base: the body's motion as the wheel encoders count it.

A real base integrates its encoders into a pose that drifts from the truth: a miscalibrated
wheel diameter scales every metre, a miscalibrated wheel base scales every turn, unequal wheels
bend straight runs, and slip adds a random walk. `WheelOdometry` integrates the body's true
per-substep motion (its velocities, not its pose, so a body placed by hand is a kidnapping the
odometry does not see) with these errors (`robots.profile.OdometrySpec`, the profile's
`[odometry]` table). The simulated base and the firmware emulators report this pose; the
body's pose stays the ground truth. Its random draws come from a generator of its own, so the
same seed gives the same run and the world's other draws do not change.
"""
from __future__ import annotations

import math

import numpy as np

from robots.profile import OdometrySpec

STREAM = 0x0D0             # mixed with the world's seed: the odometry's own random stream


def odometry_rng(seed: int) -> np.random.Generator:
    return np.random.default_rng([STREAM, int(seed)])


class WheelOdometry:
    """Pose (x, y, th) in the odometry frame (the body's start pose), measured v and w, and the
    distance and rotation counted in the last substep (`last_step`, m and rad)."""

    def __init__(self, pose: tuple[float, float, float], spec: OdometrySpec,
                 rng: np.random.Generator) -> None:
        self.x, self.y, self.th = (float(v) for v in pose)
        self.spec = spec
        self.rng = rng
        self.v = 0.0
        self.w = 0.0
        self.last_step = (0.0, 0.0)

    def step(self, v: float, w: float, dt: float) -> None:
        """The body drove at v (m/s) and w (rad/s) for dt seconds: count it, with errors."""
        if dt <= 0:
            return
        distance, rotation = v * dt, w * dt
        if distance == 0.0 and rotation == 0.0:
            self.v = self.w = 0.0
            self.last_step = (0.0, 0.0)
            return
        spec = self.spec
        measured_d = distance * (1.0 + spec.scale_error)
        measured_a = rotation * (1.0 + spec.turn_error) + spec.drift * distance
        # velocities carry the calibration error only: slip shows in the pose, not the speed
        self.v, self.w = measured_d / dt, measured_a / dt
        if spec.noise_distance or spec.noise_turn or spec.noise_heading:
            n_d, n_a = self.rng.standard_normal(2)
            measured_d += n_d * spec.noise_distance * math.sqrt(abs(distance))
            measured_a += n_a * math.sqrt(spec.noise_turn ** 2 * abs(rotation)
                                          + spec.noise_heading ** 2 * abs(distance))
        heading = self.th + measured_a / 2          # midpoint rule over a 50 ms substep
        self.x += measured_d * math.cos(heading)
        self.y += measured_d * math.sin(heading)
        self.th = math.atan2(math.sin(self.th + measured_a), math.cos(self.th + measured_a))
        self.last_step = (measured_d, measured_a)

    @property
    def pose(self) -> tuple[float, float, float]:
        return self.x, self.y, self.th
