"""The in-process simulated base: the `Base` interface over a World's body, for running the
upper layers in the simulated world before (or instead of) a wire-protocol driver. Pose and
velocities are the world's wheel odometry (which drifts from the body's true pose).

Like the P2OS firmware, it stops the body by itself when no command arrived for 2 s of sim
time, and nothing resumes motion until a new command comes.
"""
from __future__ import annotations

from dataclasses import replace

from robots.base import Base, BaseState, clamp_velocity
from robots.exceptions import LinkError
from robots.profile import Limits, load_profile
from robots.sim.world import World

WATCHDOG_TIMEOUT = 2.0      # s of sim time without a command
BATTERY_VOLTS = 12.5


class SimulatedBase(Base):
    """Drives `world.body`. Without a world it builds its own Simulation and `poll()` steps
    it to `clock.now()` (keywords: profile, clock, scenario, seed, floor)."""

    def __init__(self, limits: Limits, world: World | None = None, **kw) -> None:
        super().__init__(limits)
        self.simulation = None
        self.clock = kw.get("clock")
        if world is None:
            from robots.sim.simulation import Simulation   # only needed when standing alone
            profile = kw.get("profile") or load_profile("horos")
            profile = replace(profile, limits=limits)
            self.simulation = Simulation(profile, kw.get("scenario"), kw.get("seed", 0),
                                         self.clock, kw.get("floor"))
            world = self.simulation.world
        self.world = world
        self.is_open = False
        self.last_command_t = world.t
        self.watchdog_tripped = False
        world.hooks.append(self._watchdog)

    def open(self) -> None:
        self.is_open = True
        self.last_command_t = self.world.t

    def read_state(self) -> BaseState:
        world, body, odometry = self.world, self.world.body, self.world.odometry
        return BaseState(t=world.t, x=odometry.x, y=odometry.y, th=odometry.th, v=odometry.v,
                         w=odometry.w,
                         sonar=tuple(float(r) for r in world.sonar_ranges()),
                         bumpers=body.bumpers, stalled=body.stalled,
                         motors_enabled=self.is_open, battery=BATTERY_VOLTS,
                         link_up=self.is_open,
                         extra={"watchdog_tripped": self.watchdog_tripped})

    def command(self, v: float, w: float) -> None:
        if not self.is_open:
            raise LinkError("simulated base is not open; call open() before command()")
        v, w = clamp_velocity(v, w, self.limits)
        self.world.body.set_command(v, w)
        self.last_command_t = self.world.t
        self.watchdog_tripped = False

    def stop(self) -> None:
        self.world.body.set_command(0.0, 0.0)
        self.last_command_t = self.world.t

    def close(self) -> None:
        self.world.body.set_command(0.0, 0.0)
        self.is_open = False

    def poll(self, timeout: float = 0.0) -> None:
        """Standing alone, step the own simulation to the clock's time."""
        if self.simulation is not None and self.clock is not None:
            self.simulation.advance(self.clock.now())

    def _watchdog(self, world: World, dt: float) -> None:
        if world.t - self.last_command_t > WATCHDOG_TIMEOUT and not self.watchdog_tripped:
            world.body.set_command(0.0, 0.0)
            self.watchdog_tripped = True
