"""A simulation: the World built from a profile, a floor (given; else the scenario's `map` or
`floor`, else the office) and a scenario, kept in step with a clock. The tick loop calls `advance(clock.now())`;
in --fast runs the clock is simulated.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from robots.exceptions import FloorError, ScenarioError
from robots.profile import RobotProfile
from robots.sim.devices import SimLaser, SimPanTilt, SimPersonDetector, SimSpeaker, SimTouchScreen
from robots.sim.floor import Floor, load_floor
from robots.sim.scenario import Scenario, load_scenario
from robots.sim.world import World


def scenario_floor(scenario: Scenario | None) -> Floor:
    """The floor a scenario is written for: its `map`, its `floor`, else the office. A map
    that cannot be read is the scenario's error, at its `map` line."""
    if scenario is None:
        return load_floor("office")
    if scenario.map is not None:
        try:
            return load_floor(scenario.map)
        except FloorError as exc:
            raise ScenarioError(f"{scenario.where_field('map')}: scenario.map: {exc}") from None
    return load_floor(scenario.floor or "office")


class Simulation:
    """Owns the World; steps it up to the clock's time and hands out its devices."""

    def __init__(self, profile: RobotProfile, scenario_path: str | Path | None = None,
                 seed: int = 0, clock=None, floor: str | Path | Floor | None = None) -> None:
        self.profile = profile
        self.clock = clock
        self.scenario = load_scenario(scenario_path) if scenario_path is not None else None
        if floor is None:       # the scenario's own map or floor, else the office
            plan = scenario_floor(self.scenario)
        else:
            plan = floor if isinstance(floor, Floor) else load_floor(floor)
        self.world = World(plan, profile, self.scenario, seed)
        body = self.world.body
        self.start_pose = (body.x, body.y, body.th)    # the scenario's robot pose
        self._devices: dict | None = None

    def advance(self, now: float) -> None:
        """Step the world up to time `now`; nothing happens when `now` is not later."""
        dt = now - self.world.t
        if dt > 1e-12:
            self.world.step(dt)

    def on_step(self, callback: Callable[[World, float], None]) -> None:
        """Run `callback(world, dt)` after every world substep (e.g. lock-step emulators)."""
        self.world.hooks.append(callback)

    def devices(self) -> dict:
        """The simulated devices, made once: laser, people_detector, head, screen, speaker."""
        if self._devices is None:
            profile, world = self.profile, self.world
            self._devices = {
                "laser": SimLaser(world, profile) if profile.laser is not None else None,
                "people_detector": (SimPersonDetector(world, profile)
                                    if profile.people_detector is not None else None),
                "head": SimPanTilt(world, profile.head) if profile.head is not None else None,
                "screen": SimTouchScreen(world) if profile.touch_screen else None,
                "speaker": SimSpeaker(world),
            }
        return self._devices
