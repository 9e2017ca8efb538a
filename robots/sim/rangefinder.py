"""A laser rangefinder in the simulated world, for the laser emulators (LMS 2xx, SCIP 2.0).

Why not `World.laser_scan`: that casts the profile's beams for the in-process laser, and its
noise draws from the world's own random stream. An emulated device has its own beam layout
(the angular mode the driver chose: 181, 361 or 401 beams; a Hokuyo's 1081 steps) and must
not change what the simulated run draws. So it casts its own rays against the same walls and
the same legs (`robots.sim.raycast`), with noise from a stream of its own.

The scan is cast on the thread that steps the world (a step hook), so it never sees a world
half-way through a step; the emulator's threads only read the newest finished scan.
"""
from __future__ import annotations

import math
import threading

import numpy as np

from robots.sim.raycast import cast_rays


class WorldRangefinder:
    """Casts `angles` (rad, laser frame) from the mount (x, y, heading in the robot frame)."""

    def __init__(self, world, mount: tuple[float, float, float], max_range: float,
                 noise: float = 0.0, seed: int = 0) -> None:
        self.world = world
        self.mount = mount
        self.max_range = float(max_range)
        self.noise = float(noise)
        self.rng = np.random.default_rng([seed, 0x1A5E])
        self._lock = threading.Lock()
        self._angles = np.zeros(0)
        self._newest: tuple[float, np.ndarray] | None = None   # (world time, ranges m)

    @classmethod
    def for_profile(cls, profile, world, seed: int = 0) -> "WorldRangefinder":
        """Mounted where the profile's [laser] is (at the origin, looking ahead, without one)."""
        laser = profile.laser
        if laser is None:
            return cls(world, (0.0, 0.0, 0.0), 8.0, 0.0, seed)
        return cls(world, (laser.x, laser.y, laser.heading), laser.max_range, laser.noise, seed)

    def set_angles(self, angles: np.ndarray) -> None:
        """The beams to cast from now on (a new angular mode); forgets the old scan."""
        with self._lock:
            self._angles = np.asarray(angles, dtype=float).copy()
            self._newest = None

    def sample(self) -> None:
        """Cast a scan of the world as it is now (call from the thread that steps it)."""
        with self._lock:
            angles = self._angles
        ranges = self.cast(angles)
        with self._lock:
            if angles is self._angles:           # not a scan in a mode changed meanwhile
                self._newest = (float(self.world.t), ranges)

    def newest(self) -> tuple[float, np.ndarray] | None:
        """(world time, ranges in m; inf where nothing within max_range), or None."""
        with self._lock:
            return self._newest

    def cast(self, angles: np.ndarray) -> np.ndarray:
        """Ranges (m) along `angles` from the laser, with the laser's noise."""
        if not len(angles):
            return np.zeros(0)
        world, (mx, my, mth) = self.world, self.mount
        body = world.body
        c, s = math.cos(body.th), math.sin(body.th)
        origin = (body.x + c * mx - s * my, body.y + s * mx + c * my)
        origins = np.array([origin])                       # one for every beam
        ranges = cast_rays(origins, angles + mth + body.th, world.floor.segments,
                           world.leg_circles(), self.max_range)
        if self.noise > 0:
            hit = np.isfinite(ranges)
            ranges[hit] = np.maximum(ranges[hit] + self.rng.normal(0.0, self.noise, hit.sum()),
                                     0.0)
        return ranges
