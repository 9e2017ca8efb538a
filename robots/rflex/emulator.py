"""The rFLEX controller side, for tests and the simulated world: PERSES's firmware in software.

`RFlexController` is the firmware logic without I/O: it takes command bytes, drives a body in
the simulated world with the commanded accelerations, counts odometry per axis and produces
the reports (motor per axis, 48 sonars, bumper panels, system status). `RFlexEmulator` puts it
on a link (a raw pty or a TCP socket) and steps it either from a simulation's `on_step` hook
(lock-step with the simulated clock) or from its own real-time thread.

Failsafe: the controller zeroes both axes when no SET_DIR arrived for `FAILSAFE_TIMEOUT` =
0.5 s. The real interval is undocumented (rflex.md §8). 0.5 s is five missed 10 Hz resends, so
one late host cycle on a loaded machine does not stop the robot, and at PERSES's 0.6 m/s it
bounds the run-on before braking to 0.3 m. Nothing resumes motion afterwards but a new SET_DIR.
"""
from __future__ import annotations

import math
import socket
import threading
import time
from dataclasses import dataclass

from robots.exceptions import LinkError, ProtocolError
from robots.link import LockStep, PtyPair
from robots.rflex import protocol as p

FAILSAFE_TIMEOUT = 0.5          # s without a SET_DIR before the controller stops the axes
SONAR_PERIOD = 0.1              # s between sonar reports while sonar runs
BATTERY_RAW = 2480              # 24.8 V + 1.2 V offset = 26.0 V, a charged B21r
FRONT_PANEL, REAR_PANEL = 6, 10  # base bumper panels hit by the simulated body's front / rear
DRAIN_TIMEOUT = 1.0             # s (real) to wait for the driver's bytes in lock-step


def wrap_i32(value: int) -> int:
    return (value + 2**31) % 2**32 - 2**31


@dataclass
class Axis:
    """One motion axis as the controller keeps it (units, units/s, units/s²)."""
    target: float = 0.0
    accel: float = 0.0
    velocity: float = 0.0       # the ramped setpoint sent to the body
    position: float = 0.0       # counter, from the body's measured motion


class RFlexController:
    """Controller logic: commands in, reports out, the world's body driven in between."""

    def __init__(self, world, dist_conv: float, angle_conv: float,
                 failsafe: float = FAILSAFE_TIMEOUT, start_counts: tuple[int, int] = (0, 0)) -> None:
        self.world = world
        self.conv = (float(dist_conv), float(angle_conv))
        self.failsafe = failsafe
        self.axes = (Axis(position=start_counts[0]), Axis(position=start_counts[1]))
        self.parser = p.FrameParser(gap_timeout=None)
        self.brake = True                   # on after power-up (rflex.md §9)
        self.motor_period = 0.0             # s; 0 = reports off
        self.axis_mask = 0
        self.dio_period = 0.0
        self.sonar_on = False
        self.last_set_dir: float | None = None
        self.failsafe_stops = 0
        self.commands: list = []            # (time, decoded command), for tests and tools
        self.bad_commands = 0
        self._seq = 0
        self._next_motor = self._next_sonar = self._next_dio = 0.0
        self._panels_reported: dict[int, int] = {}
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
        return replies

    def _apply(self, command, now: float) -> bytes:
        if isinstance(command, p.SetDir):
            if command.axis in (p.TRANSLATION_AXIS, p.ROTATION_AXIS):
                axis = self.axes[command.axis]
                axis.target, axis.accel = float(command.velocity), float(command.accel)
                self.last_set_dir = now
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
            self.brake = False
        elif command in (p.Simple(p.MOT, p.MOT_BRAKE_SET), p.Simple(p.MOT, p.MOT_SET_DEFAULTS)):
            self.brake = self.brake or command.opcode == p.MOT_BRAKE_SET
            self._stop_axes()
        elif command == p.Simple(p.SYS, p.SYS_STATUS):
            return p.encode_escaped(p.status_report(self._next_seq(), p.SystemStatus(
                self._timestamp(), BATTERY_RAW, int(self.brake))))
        elif command == p.Simple(p.JSTK, p.JSTK_GET_STATE):
            return p.encode_escaped(p.joystick_report(self._next_seq(), p.JoystickReport(
                self._timestamp(), 0, 0, 0)))
        return b""

    def _stop_axes(self) -> None:
        for axis in self.axes:
            axis.target = 0.0

    # -- time -----------------------------------------------------------------------------------
    def step(self, dt: float, now: float) -> bytes:
        """The body moved for `dt`: count odometry, ramp the setpoints, return the due reports."""
        self.now = now
        body = self.world.body
        self.axes[0].position += body.v * dt * self.conv[0]
        self.axes[1].position += body.w * dt * self.conv[1]
        if (self.last_set_dir is not None and now - self.last_set_dir > self.failsafe
                and any(a.target for a in self.axes)):
            self._stop_axes()
            self.failsafe_stops += 1
        for axis in self.axes:
            target = 0.0 if self.brake else axis.target
            step = axis.accel * dt
            axis.velocity = min(target, axis.velocity + step) if target > axis.velocity \
                else max(target, axis.velocity - step)
            if self.brake:
                axis.velocity = 0.0
        body.set_command(self.axes[0].velocity / self.conv[0], self.axes[1].velocity / self.conv[1])
        return self._due_reports(now)

    def _due_reports(self, now: float) -> bytes:
        out = b""
        if self.motor_period > 0 and now >= self._next_motor - 1e-9:
            self._next_motor = _next_time(self._next_motor, self.motor_period, now)
            out += self._motor_reports()
        if self.sonar_on and now >= self._next_sonar - 1e-9:
            self._next_sonar = _next_time(self._next_sonar, SONAR_PERIOD, now)
            out += self._sonar_report()
        if self.dio_period > 0 and now >= self._next_dio - 1e-9:
            self._next_dio = _next_time(self._next_dio, self.dio_period, now)
            out += self._dio_reports()
        return out

    def _motor_reports(self) -> bytes:
        body = self.world.body
        measured = (body.v * self.conv[0], body.w * self.conv[1])
        out = b""
        for index, axis in enumerate(self.axes):
            if self.axis_mask & (1 << index):
                report = p.MotorReport(0, self._timestamp(), index, wrap_i32(round(axis.position)),
                                       wrap_i32(round(measured[index])), round(axis.accel) & 0x7FFFFFFF,
                                       0)
                out += p.encode_escaped(p.motor_report(self._next_seq(), report))
        return out

    def _sonar_report(self) -> bytes:
        ranges = self.world.sonar_ranges()
        readings = tuple((p.SONAR_WIRE_IDS[i], p.sonar_raw(float(r)))
                         for i, r in enumerate(ranges[:p.SONAR_COUNT]))
        return p.encode_escaped(p.sonar_report(self._next_seq(),
                                               p.SonarReport(0, self._timestamp(), readings)))

    def _dio_reports(self) -> bytes:
        """Every pressed panel each period, and each release once."""
        pressed = {}
        bumpers = int(self.world.bumpers)
        if bumpers & 1:
            pressed[FRONT_PANEL] = 0x3
        if bumpers & 2:
            pressed[REAR_PANEL] = 0xC
        out = b""
        for panel in sorted(set(pressed) | set(self._panels_reported)):
            data = pressed.get(panel, 0)
            out += p.encode_escaped(p.dio_report(self._next_seq(), p.DioReport(
                self._timestamp(), p.BUMPER_FIRST_ADDRESS + panel, data)))
        self._panels_reported = pressed
        return out

    def _next_seq(self) -> int:
        self._seq = (self._seq + 1) & 0xFF
        return self._seq

    def _timestamp(self) -> int:
        return int(self.now * 1000) & p.U32_MAX     # ms; unknown on the real controller


def _next_time(scheduled: float, period: float, now: float) -> float:
    """The next report time on the grid of whole periods after `now` (reports fall on 0.1 s
    marks of controller time; after a stall the controller skips ahead rather than bursting)."""
    return (math.floor(now / period + 1e-6) + 1) * period


# --------------------------------------------------------------------------- links

class TcpLink:
    """A one-client TCP server with the PtyPair read/write/close shape (for `--tcp PORT`)."""

    def __init__(self, port: int, host: str = "127.0.0.1") -> None:
        self.server = socket.create_server((host, port))
        self.server.settimeout(0.1)
        self.port = self.server.getsockname()[1]
        self.path = f"socket://{host}:{self.port}"
        self.client: socket.socket | None = None
        self.closed = False

    def _accept(self, timeout: float | None) -> bool:
        if self.client is not None:
            return True
        self.server.settimeout(timeout if timeout is not None else 0.1)
        try:
            self.client, _ = self.server.accept()
        except (socket.timeout, OSError):
            return False
        self.client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        return True

    def read(self, size: int = 4096, timeout: float | None = None) -> bytes:
        if not self._accept(timeout):
            return b""
        self.client.settimeout(timeout)
        try:
            data = self.client.recv(size)
        except socket.timeout:
            return b""
        except OSError:
            data = b""
        if not data:                       # the driver hung up: wait for the next one
            self.client.close()
            self.client = None
        return data

    def write(self, data: bytes) -> None:
        if self.client is None:
            return
        try:
            self.client.sendall(data)
        except OSError:
            self.client.close()
            self.client = None

    def close(self) -> None:
        self.closed = True
        if self.client is not None:
            self.client.close()
        self.server.close()


class RFlexEmulator:
    """An `RFlexController` on a link. Lock-step: `attach(simulation)`; real time: `start()`."""

    def __init__(self, world, link: PtyPair | TcpLink | None = None, *, dist_conv: float,
                 angle_conv: float, lockstep: LockStep | None = None, clock=None,
                 failsafe: float = FAILSAFE_TIMEOUT, start_counts: tuple[int, int] = (0, 0)) -> None:
        self.world = world
        self.link = link if link is not None else PtyPair()
        self.lockstep = lockstep
        self.clock = clock
        self.controller = RFlexController(world, dist_conv, angle_conv, failsafe, start_counts)
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._running = False
        self.unplugged = False

    @property
    def path(self) -> str:
        return self.link.path

    # -- lock-step with a simulation ------------------------------------------------------------
    def attach(self, simulation) -> None:
        """Run inside `simulation.advance`: after every world substep, take the commands the
        driver has written, update the controller and write the reports that fell due."""
        simulation.on_step(self.on_step)

    def on_step(self, world, dt: float) -> None:
        if self.unplugged:
            return
        with self._lock:
            self._pump_commands(world.t)
            self._write(self.controller.step(dt, world.t))

    def _pump_commands(self, now: float) -> None:
        """Read what the driver wrote; in lock-step, wait (real time) until all of it is here."""
        deadline = time.monotonic() + DRAIN_TIMEOUT
        counter = self.lockstep.to_device if self.lockstep is not None else None
        while True:
            data = self.link.read(4096, timeout=0)
            if data:
                if counter is not None:
                    counter.got(len(data))
                self._write(self.controller.receive(data, now))
                continue
            if counter is None or counter.backlog() <= 0 or time.monotonic() > deadline:
                return
            data = self.link.read(4096, timeout=0.01)
            if data:
                if counter is not None:
                    counter.got(len(data))
                self._write(self.controller.receive(data, now))

    def _write(self, data: bytes) -> None:
        if not data or self.unplugged:
            return
        if self.lockstep is not None:
            self.lockstep.to_host.wrote(len(data))
        try:
            self.link.write(data)
        except LinkError:
            self.unplugged = True

    # -- real time ------------------------------------------------------------------------------
    def start(self, step: float = 0.01, own_world: bool = True) -> "RFlexEmulator":
        """Serve in a thread of our own, stepping the world (if `own_world`) in real time."""
        self._running = True
        self._thread = threading.Thread(target=self._serve, args=(step, own_world),
                                        name="rflex-emulator", daemon=True)
        self._thread.start()
        return self

    def _serve(self, step: float, own_world: bool) -> None:
        start = time.monotonic()
        last = 0.0
        while self._running and not self.unplugged:
            data = self.link.read(4096, timeout=step)
            now = time.monotonic() - start
            with self._lock:
                if data:
                    self._write(self.controller.receive(data, now))
                dt = now - last
                if dt >= step:
                    if own_world:
                        self.world.step(dt)
                    self._write(self.controller.step(dt, now))
                    last = now

    def unplug(self) -> None:
        """Pull the cable: both ends of the link close; the driver sees an error or silence."""
        self.unplugged = True
        self.link.close()

    def stop(self) -> None:
        self._running = False
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=1.0)
        self._thread = None

    def close(self) -> None:
        self.stop()
        self.unplugged = True
        self.link.close()
