"""The device interfaces of `robots.devices` implemented over a simulated World."""
from __future__ import annotations

import math

from robots.devices import (Detection, Laser, LaserScan, PanTiltHead, PersonDetector, Speaker,
                            TouchScreen)
from robots.profile import HeadSpec, RobotProfile
from robots.sim.world import World


class SimLaser(Laser):
    """Casts a fresh scan of the world on each read. `rng`: a random stream of its own for the
    range errors (a second reader, such as the start-up self-check, leaves the run's alone)."""

    def __init__(self, world: World, profile: RobotProfile, rng=None) -> None:
        if profile.laser is None:
            raise ValueError(f"robot '{profile.name}' has no laser")
        self.world = world
        self.spec = profile.laser
        self.rng = rng

    def read(self) -> LaserScan:
        angles, ranges = self.world.laser_scan(self.rng)
        return LaserScan(t=self.world.t, angles=angles, ranges=ranges,
                         origin=(self.spec.x, self.spec.y, self.spec.heading))


class SimPersonDetector(PersonDetector):
    """The camera stand-in: detections in the robot frame with the spec's noise as covariance."""

    def __init__(self, world: World, profile: RobotProfile) -> None:
        if profile.people_detector is None:
            raise ValueError(f"robot '{profile.name}' has no people detector")
        self.world = world
        variance = profile.people_detector.noise ** 2
        self.cov = ((variance, 0.0), (0.0, variance))

    def detect(self) -> list[Detection]:
        t = self.world.t
        return [Detection(t, x, y, self.cov, "camera", look)
                for x, y, look in self.world.person_detections()]


class SimPanTilt(PanTiltHead):
    """Moves `world.head_pan`, `head_tilt` towards the target at the head's rate as the world
    steps."""

    def __init__(self, world: World, spec: HeadSpec) -> None:
        self.world = world
        self.spec = spec
        self.target = (world.head_pan, world.head_tilt)
        world.hooks.append(self._move)

    def point(self, pan: float, tilt: float) -> None:
        spec = self.spec
        pan = _clamp(pan, spec.pan_min, spec.pan_max, self.target[0])
        tilt = _clamp(tilt, spec.tilt_min, spec.tilt_max, self.target[1])
        self.target = (pan, tilt)

    def read(self) -> tuple[float, float]:
        return self.world.head_pan, self.world.head_tilt

    def _move(self, world: World, dt: float) -> None:
        step = self.spec.max_pan_rate * dt
        world.head_pan = _towards(world.head_pan, self.target[0], step)
        world.head_tilt = _towards(world.head_tilt, self.target[1], step)


def _clamp(value: float, low: float, high: float, fallback: float) -> float:
    """`value` within [low, high]; a NaN keeps the previous target (safe: no jump)."""
    value = float(value)
    if math.isnan(value):
        return fallback
    return min(high, max(low, value))


def _towards(current: float, target: float, step: float) -> float:
    if target > current:
        return min(target, current + step)
    return max(target, current - step)


class SimTouchScreen(TouchScreen):
    """Shows prompts on `world.screen`, where simulated people press the buttons."""

    source = "sim"

    def __init__(self, world: World) -> None:
        self.world = world

    def show(self, prompt_id: str, text: str, buttons: tuple[str, ...],
             typed: bool = False) -> None:
        self.world.screen.show(prompt_id, text, tuple(buttons), self.world.t, typed)

    def display(self, text: str, picture: str | None = None) -> None:
        self.world.screen.display(text, picture)

    def caption(self, text: str) -> None:
        self.world.screen.caption = text

    def clear(self) -> None:
        self.world.screen.clear()

    def take_press(self) -> tuple[str, str] | None:
        return self.world.screen.take_press()


class SimSpeaker(Speaker):
    """Records utterances in `world.utterances`; busy ~0.06 s of sim time per character."""

    def __init__(self, world: World) -> None:
        self.world = world

    def say(self, text: str) -> None:
        self.world.say(text)

    def busy(self) -> bool:
        return self.world.t < self.world.speaking_until
