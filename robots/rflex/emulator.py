"""The rFLEX controller side, for tests and the simulated world: PERSES's firmware in software.

`RFlexController` is the firmware logic without I/O: it takes command bytes, drives the world's
body, counts odometry per axis (the world's drifting wheel odometry, `robots.sim.odometry`) and
produces the reports (motor per axis, the 48 sonars, bumper panels, system status). `RFlexEmulator` puts it on a transport (a raw pty or a TCP port) in the
same shape as the P2OS emulator, so `interbot emulate` can host either:
- a reader thread applies commands as they arrive (in lock-step, before the driver's write
  returns, so a command written before `advance` is in force for the whole next step);
- reports are produced in the simulation's step hook on the 100 ms grid of world time; standing
  alone, `start_clock(simulation)` steps the simulation in real time.

Acceleration: the body ramps towards the commanded velocities with the profile's physical
limits, capped further by the acceleration each SET_DIR carries (units/s², as the controller
would ramp).

Commands the notes describe but the simulated base has nothing for are accepted and counted in
`ignored` (see docs/emulator-fidelity.md): IR_RUN (no IR ring is simulated), DIO_SET (no digital
outputs), SYS_LCD_DUMP (no display). MOT_AXIS_SET_POS sets the axis's position counter and stops
that axis (CARMEN sends it with zeros to reset odometry; what a moving SET_POS does is not
known, so the safe reading is taken). While DIO reports run, the bearing passing its home
(world heading 0) is reported as a DIO report at address 0x31, the B21's heading-home event.

Failsafe: the controller zeroes both axes when no SET_DIR arrived for `FAILSAFE_TIMEOUT` =
0.5 s of controller time. The real interval is undocumented (rflex.md §8). 0.5 s is five missed
10 Hz resends, so one late host cycle on a loaded machine does not stop the robot, and at
PERSES's 0.6 m/s it bounds the run-on to 0.3 m before braking. Nothing resumes motion
afterwards but a new SET_DIR.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from robots.exceptions import ProtocolError
from robots.link import LockStep
from robots.link.host import EmulatorHost
from robots.rflex import protocol as p

FAILSAFE_TIMEOUT = 0.5          # s without a SET_DIR before the controller stops the axes
SONAR_PERIOD = 0.1              # s between sonar reports while sonar runs
BATTERY_RAW = 2480              # 24.80 + 1.2 V offset = 26.0 V, a charged B21r
FRONT_PANEL, REAR_PANEL = 6, 10  # base bumper panels hit by the simulated body's front / rear
WORLD_BUMPER_FRONT, WORLD_BUMPER_REAR = 1, 2
DIST_CONV, ANGLE_CONV = 101230.0, 35343.888   # CARMEN b21r+, as robots/profiles/perses.toml


def wrap_i32(value: int) -> int:
    return (value + 2**31) % 2**32 - 2**31


@dataclass
class Axis:
    """One motion axis as the controller keeps it (units/s, units/s², units)."""
    target: float = 0.0
    accel: float = 0.0
    position: float = 0.0       # counter, from the body's measured motion


class RFlexController:
    """Controller logic: commands in, reports out, the world's body driven in between."""

    def __init__(self, world, dist_conv: float = DIST_CONV, angle_conv: float = ANGLE_CONV,
                 failsafe: float = FAILSAFE_TIMEOUT, start_counts: tuple[int, int] = (0, 0)) -> None:
        self.world = world
        self.conv = (float(dist_conv), float(angle_conv))
        self.failsafe = failsafe
        self.axes = (Axis(position=start_counts[0]), Axis(position=start_counts[1]))
        self.parser = p.FrameParser(gap_timeout=None)
        self.physical_limits = world.body.limits
        self.brake = True                   # on after power-up (rflex.md §9)
        self.estop = False                  # the e-stop held: brake set, release ignored (tests)
        self.defaults_stop_axes = True      # our reading of MOT_SET_DEFAULTS; False: a controller
                                            # whose defaults leave the velocity alone (tests)
        self.motor_period = 0.0             # s; 0 = reports off
        self.axis_mask = 0
        self.dio_period = 0.0
        self.sonar_on = False
        self.last_set_dir: float | None = None
        self.failsafe_stops = 0
        self.commands: list = []            # (time, decoded command), for tests and tools
        self.bad_commands = 0
        self.ignored = 0                    # accepted commands with no effect here (see above)
        self._last_heading: float | None = None
        self._home_pending = False
        self._seq = 0
        self._next_motor = self._next_sonar = self._next_dio = 0.0
        self._panels_reported: dict[int, int] = {}
        self._limits_of = self._limits_key = None   # what `_limits` was built from (`_drive`)
        self._limits = None
        self.now = 0.0

    # -- commands -----------------------------------------------------------------------------
    def receive(self, data: bytes, now: float) -> bytes:
        """Apply the commands in `data`; return the immediate replies (status, joystick)."""
        self.now = now
        replies = b""
        for frame in self.parser.feed(data):
            try:
                command = p.decode_command(frame)
            except ProtocolError:
                self.bad_commands += 1
                continue
            self.commands.append((now, command))
            replies += self._apply(command, now)
        self._drive()
        return replies

    def _apply(self, command, now: float) -> bytes:
        if isinstance(command, p.SetDir):
            if command.axis in (p.TRANSLATION_AXIS, p.ROTATION_AXIS):
                axis = self.axes[command.axis]
                axis.target, axis.accel = float(command.velocity), float(command.accel)
                self.last_set_dir = now
        elif isinstance(command, p.SetPos):
            if command.axis in (p.TRANSLATION_AXIS, p.ROTATION_AXIS):
                axis = self.axes[command.axis]
                axis.position, axis.target = float(command.position), 0.0
        elif isinstance(command, p.ReportRequest):
            self.motor_period, self.axis_mask = command.period_us / 1e6, command.axis_mask
            self._next_motor = now
        elif isinstance(command, p.DioRequest):
            self.dio_period = command.period_us / 1e6
            self._next_dio = now
        elif isinstance(command, p.SonarRun):
            self.sonar_on = command.on
            self._next_sonar = now
        elif command == p.Simple(p.MOT, p.MOT_BRAKE_RELEASE):
            self.brake = self.estop         # the e-stop holds the brake (our reading)
        elif command == p.Simple(p.MOT, p.MOT_BRAKE_SET):
            self.brake = True
            self._stop_axes()
        elif command == p.Simple(p.MOT, p.MOT_SET_DEFAULTS):
            if self.defaults_stop_axes:
                self._stop_axes()
        elif command == p.Simple(p.SYS, p.SYS_STATUS):
            return p.encode_escaped(p.status_report(self._next_seq(), p.SystemStatus(
                self._timestamp(), BATTERY_RAW, int(self.brake))))
        elif command == p.Simple(p.JSTK, p.JSTK_GET_STATE):
            return p.encode_escaped(p.joystick_report(self._next_seq(), p.JoystickReport(
                self._timestamp(), 0, 0, 0)))
        else:                               # IR_RUN, DIO_SET, SYS_LCD_DUMP: nothing to do it on
            self.ignored += 1
        return b""

    def _stop_axes(self) -> None:
        for axis in self.axes:
            axis.target = 0.0

    def press_estop(self, held: bool = True) -> None:
        """The e-stop (tests): pressed, the brake is set and the axes stop; released, the
        brake stays set until the host releases it."""
        self.estop = held
        if held:
            self.brake = True
            self._stop_axes()
            self._drive()

    def hang_up(self) -> None:
        """The host went away (a TCP take-over or hang-up): what the driver's own stop sequence
        leaves (axes at zero, reports and sonar off, brake set), so the next client inherits
        no velocity and no released brake."""
        self._stop_axes()
        self.brake = True
        self.motor_period, self.axis_mask, self.dio_period = 0.0, 0, 0.0
        self.sonar_on = False
        self.last_set_dir = None
        self._drive()

    def _drive(self) -> None:
        """Hand the targets to the body, ramped at min(physical, commanded) acceleration."""
        body = self.world.body
        if self.brake:
            body.set_command(0.0, 0.0)
            return
        translation, rotation = self.axes
        limits = self.physical_limits
        key = (translation.accel, rotation.accel, self.conv)
        if limits is not self._limits_of or key != self._limits_key:   # a new Limits only
            self._limits_of, self._limits_key = limits, key              # when the ramp changes
            self._limits = replace(
                limits,
                max_accel=_cap(limits.max_accel, translation.accel / self.conv[0]),
                max_turn_accel=_cap(limits.max_turn_accel, rotation.accel / self.conv[1]))
        body.limits = self._limits
        body.set_command(translation.target / self.conv[0], rotation.target / self.conv[1])

    # -- time -----------------------------------------------------------------------------------
    def step(self, dt: float, now: float) -> bytes:
        """The body moved for `dt`: count odometry, apply the failsafe, return the due reports."""
        self.now = now
        body = self.world.body
        odometry = getattr(self.world, "odometry", None)   # None in a bare stand-in world
        distance, rotation = (odometry.last_step if odometry is not None
                              else (body.v * dt, body.w * dt))
        self.axes[0].position += distance * self.conv[0]
        self.axes[1].position += rotation * self.conv[1]
        self._watch_home(body.th)
        if (self.last_set_dir is not None and now - self.last_set_dir > self.failsafe
                and any(a.target for a in self.axes)):
            self._stop_axes()
            self._drive()
            self.failsafe_stops += 1
        return self._due_reports(now)

    def _watch_home(self, heading: float) -> None:
        """The bearing passed home (world heading 0, not the ±pi wrap): report it next."""
        last, self._last_heading = self._last_heading, heading
        if last is not None and last != heading and last * heading <= 0 \
                and abs(last - heading) < math.pi:
            self._home_pending = True

    def _due_reports(self, now: float) -> bytes:
        out = b""
        if self._home_pending and self.dio_period > 0:
            self._home_pending = False
            out += p.encode_escaped(p.dio_report(self._next_seq(), p.DioReport(
                self._timestamp(), p.HOME_ADDRESS, 1)))
        if self.motor_period > 0 and now >= self._next_motor - 1e-9:
            self._next_motor = _next_time(self.motor_period, now)
            out += self._motor_reports()
        if self.sonar_on and now >= self._next_sonar - 1e-9:
            self._next_sonar = _next_time(SONAR_PERIOD, now)
            out += self._sonar_report()
        if self.dio_period > 0 and now >= self._next_dio - 1e-9:
            self._next_dio = _next_time(self.dio_period, now)
            out += self._dio_reports()
        return out

    def _motor_reports(self) -> bytes:
        moving = getattr(self.world, "odometry", self.world.body)
        measured = (moving.v * self.conv[0], moving.w * self.conv[1])
        out = b""
        for index, axis in enumerate(self.axes):
            if self.axis_mask & (1 << index):
                report = p.MotorReport(0, self._timestamp(), index, wrap_i32(round(axis.position)),
                                       wrap_i32(round(measured[index])),
                                       min(round(axis.accel), 2**31 - 1), 0)
                out += p.encode_escaped(p.motor_report(self._next_seq(), report))
        return out

    def _sonar_report(self) -> bytes:
        ranges = np.asarray(self.world.sonar_ranges(), dtype=float)[:p.SONAR_COUNT].tolist()
        return p.encode_escaped(p.sonar_report_of_raws(self._next_seq(), 0, self._timestamp(),
                                                       [p.sonar_raw(r) for r in ranges]))

    def _dio_reports(self) -> bytes:
        """Every pressed panel each period, and each release once."""
        pressed = {}
        bumpers = int(self.world.bumpers)
        if bumpers & WORLD_BUMPER_FRONT:
            pressed[FRONT_PANEL] = 0x3
        if bumpers & WORLD_BUMPER_REAR:
            pressed[REAR_PANEL] = 0xC
        out = b""
        for panel in sorted(set(pressed) | set(self._panels_reported)):
            out += p.encode_escaped(p.dio_report(self._next_seq(), p.DioReport(
                self._timestamp(), p.BUMPER_FIRST_ADDRESS + panel, pressed.get(panel, 0))))
        self._panels_reported = pressed
        return out

    def _next_seq(self) -> int:
        self._seq = (self._seq + 1) & 0xFF
        return self._seq

    def _timestamp(self) -> int:
        return round(self.now * 1000) & p.U32_MAX   # ms; unknown on the real controller


def _cap(physical: float, commanded: float) -> float:
    return min(physical, commanded) if commanded > 0 else physical


def _next_time(period: float, now: float) -> float:
    """The next whole multiple of `period` after `now`: reports fall on the 100 ms grid of
    controller time, and after a stall the controller skips ahead rather than bursting."""
    return (math.floor(now / period + 1e-6) + 1) * period


# --------------------------------------------------------------------------- transports

# --------------------------------------------------------------------------- the emulator

class RFlexEmulator(EmulatorHost):
    """An `RFlexController` on a pty or TCP port, around `world` (see the module docstring)."""

    name = "rflex-emulator"

    def __init__(self, world, *, dist_conv: float = DIST_CONV, angle_conv: float = ANGLE_CONV,
                 clock=None, lockstep: LockStep | None = None, failsafe: float = FAILSAFE_TIMEOUT,
                 start_counts: tuple[int, int] = (0, 0)) -> None:
        super().__init__(lockstep)
        self.world = world
        self.clock = clock
        self.controller = RFlexController(world, dist_conv, angle_conv, failsafe, start_counts)
        self._hooked = False

    @classmethod
    def for_profile(cls, profile, world, **kw) -> "RFlexEmulator":
        """An emulator with `profile`'s conversion factors (the `interbot emulate` factory)."""
        options = profile.base.options
        return cls(world, dist_conv=options.get("dist_conv", DIST_CONV),
                   angle_conv=options.get("angle_conv", ANGLE_CONV), **kw)

    def press_estop(self, held: bool = True) -> None:
        """The e-stop, pressed or released (tests; `RFlexController.press_estop`)."""
        with self._lock:
            self.controller.press_estop(held)

    # -- time -----------------------------------------------------------------------------------
    def attach(self, simulation) -> None:
        """Produce reports in the simulation's step hook (world time)."""
        if not self._hooked:
            simulation.on_step(self.on_step)
            self._hooked = True

    def on_step(self, world, dt: float) -> None:
        with self._lock:
            self._send(self.controller.step(dt, float(world.t)))

    def start_clock(self, simulation=None, period: float = 0.01) -> None:
        """Standing alone: a thread steps `simulation` to the clock's time every `period` s."""
        if simulation is None:
            return

        def run() -> None:
            while not self._stop.wait(period):
                simulation.advance(self.clock.now())
        self._spawn(run, "rflex-emulator-clock")

    # -- hosting hooks (robots.link.host) -----------------------------------------------------
    def on_connect(self) -> None:
        self.controller.parser.reset()

    def on_hangup(self) -> None:
        """The client left or another took over: stopped, brake set (robots.link.host)."""
        self.controller.hang_up()

    def receive(self, data: bytes) -> None:
        """Bytes from the driver: apply, answer, then count them as read (lock-step)."""
        with self._lock:
            self._send(self.controller.receive(data, float(self.world.t)))
        if self.lockstep is not None:
            self.lockstep.to_device.got(len(data))
