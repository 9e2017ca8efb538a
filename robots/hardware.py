"""Open a whole robot: its base and devices, on real hardware or in the simulated world.

`open_hardware` is the one door from L1 into L0. Without a port the robot lives in the
simulated world; where the base's driver can talk to a firmware emulator (it has a
`for_simulation` classmethod), the real driver speaks its wire protocol to the emulator,
otherwise the in-process simulated base stands in.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from robots.base import Base, base_classes
from robots.clock import RealClock, SimClock
from robots.devices import Laser, PanTiltHead, PersonDetector, Speaker, TouchScreen
from robots.exceptions import RobotError
from robots.profile import RobotProfile, load_profile


@dataclass
class Hardware:
    """Everything L1 may touch on one robot, plus the simulation when there is one."""
    profile: RobotProfile
    clock: SimClock | RealClock
    base: Base
    laser: Laser | None = None
    people_detector: PersonDetector | None = None
    head: PanTiltHead | None = None
    screen: TouchScreen | None = None
    speaker: Speaker | None = None
    simulation: object | None = None     # robots.sim.simulation.Simulation in simulation
    closed: bool = field(default=False, init=False)

    @property
    def capabilities(self) -> frozenset[str]:
        """What this robot can do as opened: the profile's devices that are actually present.

        On a real robot only the base (and its sonar) is driven so far, so a profile's laser,
        camera, head or touch screen count only when a device object stands behind them."""
        present = {"base", "speech_out"} if self.speaker is not None else {"base"}
        if self.profile.sonar is not None:
            present.add("sonar")
        for capability, device in (("laser", self.laser), ("people_detector", self.people_detector),
                                   ("pan_tilt", self.head), ("touch_screen", self.screen)):
            if device is not None:
                present.add(capability)
        return frozenset(present & self.profile.capabilities)

    def sense(self) -> float:
        """Bring the world (if simulated) and the base up to now; returns robot time."""
        now = self.clock.now()
        if self.simulation is not None:
            self.simulation.advance(now)
        self.base.poll()
        return now

    @property
    def scenario_duration(self) -> float | None:
        """The simulated scenario's suggested run length, s (None on a real robot)."""
        scenario = getattr(self.simulation, "scenario", None)
        return scenario.duration if scenario is not None else None

    @property
    def scenario_people(self) -> int | None:
        """How many people the simulated scenario brings (None on a real robot)."""
        if self.simulation is None:
            return None
        scenario = getattr(self.simulation, "scenario", None)
        return len(scenario.people) if scenario is not None else 0

    @property
    def start_pose(self) -> tuple[float, float, float] | None:
        """Where the simulated robot started (x, y, heading rad; None on a real robot)."""
        return getattr(self.simulation, "start_pose", None)

    @property
    def floor(self):
        """The simulated floor (robots.sim.floor.Floor; None on a real robot)."""
        world = getattr(self.simulation, "world", None)
        return world.floor if world is not None else None

    def ground_truth(self) -> list[tuple[str, float, float]]:
        """Where the simulated people really are (empty on a real robot)."""
        if self.simulation is None:
            return []
        return self.simulation.world.ground_truth()

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        try:
            self.base.stop()
        finally:
            self.base.close()


def open_hardware(robot: str | Path, *, port: str | None = None, scenario: str | Path | None = None,
                  fast: bool = False, seed: int = 0, emulate: bool = True,
                  floor: str | Path = "office") -> Hardware:
    """Open `robot` (a profile name or path). `port` drives a real base; otherwise simulate.

    `emulate=False` forces the in-process simulated base even where an emulator exists;
    `floor` is the simulated building (a bundled floor name or a floor .toml).
    """
    profile = load_profile(robot)
    clock = SimClock() if fast else RealClock()
    if port is not None:
        return _open_real(profile, clock, port)
    return _open_simulated(profile, clock, scenario, seed, emulate, floor)


def _driver_class(profile: RobotProfile) -> type[Base] | None:
    return base_classes().get(profile.base.driver)


def _open_real(profile: RobotProfile, clock, port: str) -> Hardware:
    """A real base at `port`; a driver may configure itself from the profile (`for_profile`)."""
    driver = _driver_class(profile)
    if driver is None:
        known = ", ".join(sorted(base_classes()))
        raise RobotError(f"robot '{profile.name}' needs base driver '{profile.base.driver}', "
                         f"which is not installed (installed: {known})")
    if hasattr(driver, "for_profile"):
        base = driver.for_profile(profile, port, clock=clock)
    else:
        base = driver(profile.limits, port, clock=clock, **profile.base.options)
    try:
        base.open()
    except BaseException:         # a link error, or a signal in the middle of the handshake
        base.close()
        raise
    # On a real robot the devices other than the base are not wired up yet; speech is printed.
    from robots.console import ConsoleSpeaker
    return Hardware(profile=profile, clock=clock, base=base, speaker=ConsoleSpeaker(clock))


def _open_simulated(profile: RobotProfile, clock, scenario, seed: int, emulate: bool,
                    floor: str | Path = "office") -> Hardware:
    from robots.sim.base import SimulatedBase
    from robots.sim.simulation import Simulation

    simulation = Simulation(profile, scenario, seed, clock, floor)
    driver = _driver_class(profile)
    if emulate and driver is not None and hasattr(driver, "for_simulation"):
        base = driver.for_simulation(profile, simulation, clock)
    else:
        base = SimulatedBase(profile.limits, world=simulation.world)
    base.open()
    devices = simulation.devices()
    return Hardware(profile=profile, clock=clock, base=base, simulation=simulation,
                    laser=devices.get("laser"), people_detector=devices.get("people_detector"),
                    head=devices.get("head"), screen=devices.get("screen"),
                    speaker=devices.get("speaker"))
