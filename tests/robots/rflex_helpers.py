"""Small stand-ins shared by the rFLEX tests: an empty world and a simulation that steps it."""
from __future__ import annotations

import math
import time

import numpy as np

from robots.profile import load_profile
from robots.sim.body import UnicycleBody

PERSES = load_profile("perses")


class BoxWorld:
    """A body in empty space with sonar ranges and bumpers the test sets."""

    def __init__(self, limits=PERSES.limits) -> None:
        self.body = UnicycleBody(0.0, 0.0, 0.0, limits, 0.26)
        self.t = 0.0
        self.bumpers = 0
        self.ranges = np.full(48, math.inf)

    def step(self, dt: float) -> None:
        self.body.step(dt)
        self.t += dt

    def sonar_ranges(self) -> np.ndarray:
        return self.ranges


class StepSim:
    """Just enough of robots.sim.Simulation: `world`, `on_step`, `advance` in 50 ms substeps."""

    def __init__(self, world: BoxWorld) -> None:
        self.world = world
        self.hooks = []

    def on_step(self, callback) -> None:
        self.hooks.append(callback)

    def advance(self, now: float) -> None:
        while self.world.t < now - 1e-9:
            h = min(0.05, now - self.world.t)
            self.world.step(h)
            for hook in self.hooks:
                hook(self.world, h)


def wait_until(predicate, timeout: float = 5.0, every: float = 0.005) -> bool:
    """Poll `predicate` until it holds or `timeout` s pass (for real-time link tests)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(every)
    return predicate()
