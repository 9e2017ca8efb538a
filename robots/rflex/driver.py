"""The host side of rFLEX: `RFlexBase`, PERSES's B21r base on any pyserial URL.

Start sequence (rflex.md §7): motor reports for both axes and DIO reports at 10 Hz, set
defaults, release the brake, zero on both axes, sonar on, one status request. Then both
SET_DIR frames (translation, rotation) go out every 100 ms **always, zeros included**, and
the watchdog sends zero on its own 150 ms after the last fresh `command()`.

Conversion factors default to CARMEN's "b21r+" values (101230 units/m, 35343.888 units/rad),
the same ones `robots/profiles/perses.toml` carries; Player and ROS use 103000 / 35000. All are
empirical: calibrate on the robot (rflex.md §6).

Odometry: the two axes report in separate frames; a pose update happens only when both are
fresh, with signed 32-bit wrapping deltas, the heading from the bearing axis (synchro drive)
and the translation applied along the mid-step heading.

Link and faults: everything that has arrived is read in one call and only the newest
FLOOD_KEEP bytes of a flood are decoded (`robots.link.arrival`); a motor report older than
LINK_TIMEOUT means the link is stale: the command is zeroed at once (the stale-link stop) and
commands are kept out until reports return. SYS_STATUS is asked once a second; a brake the
controller set by itself after we released it is a drive fault (zero, commands ignored,
`extra["fault_device"]` for the trace's `fault` event) until the driver is closed, or until
`reset_faults()` (with the option `reset_faults`): zero on both axes, MOT_BRAKE_RELEASE and a
status request once no motion is commanded; the fault clears when SYS_STATUS reports the brake
released (`robots.link.fault_reset`), and the command stays zero until the next `command()`.

Two ways to run: in real time an I/O thread reads, resends and reconnects while the watchdog
has its own thread; on a simulated clock (lock-step with an in-process emulator) `poll()` does
the same work deterministically, waiting (real-time timeout) for the emulator's bytes.
"""
from __future__ import annotations

import io
import math
import select
import threading
import time

import serial

from robots.base import Base, BaseState, clamp_velocity
from robots.exceptions import FaultResetError, LinkError, ProfileError, ProtocolError
from robots.link import Backoff, CommandWatchdog, LockStep
from robots.link.arrival import read_arrived
from robots.link.fault_reset import FaultReset
from robots.link.port import open_serial
from robots.profile import Limits
from robots.rflex import protocol as p

DIST_CONV = 101230.0          # units/m, CARMEN b21r+ (Player/ROS: 103000)
ANGLE_CONV = 35343.888        # units/rad, CARMEN b21r+ (Player/ROS: 35000)
BAUD = 115200
RESEND_PERIOD = 0.1           # s: both axes at 10 Hz, always
# s: a caller that commanded this recently resends itself (its next command goes out when
# due): the driver's own resend waits, so the two never go out back to back
CALLER_RESENDS = 1.5 * RESEND_PERIOD
WATCHDOG_TIMEOUT = 0.15       # s: zero goes out within 200 ms of the last fresh command
LINK_TIMEOUT = 0.35           # s without a report: link down (three missed 10 Hz reports and a
                              # half, as the P2OS driver: silence is noticed within 0.5 s)
FLOOD_KEEP = 16384            # bytes of one read parsed at most: the newest of a flood
RESTART_PERIOD = 1.0          # s between start sequences while the controller is silent
STATUS_PERIOD = 1.0           # s between SYS_STATUS requests, driving or not: a brake set by
                              # itself is a fault within about a second (Player asks every
                              # cycle; ROS every 100th: "overwhelms the driver")
FRAME_GAP = 0.001             # s after each frame in real time ("not recognised if too rapid")
LOCKSTEP_TIMEOUT = 1.0        # s (real) to wait for the emulator's reports in lock-step
OPTIONS = ("dist_conv", "angle_conv", "baud", "accel", "reset_faults")


class RFlexBase(Base):
    """A B21r base over rFLEX. `url` is any pyserial URL (`/dev/ttyUSB0`, `socket://h:p`)."""

    PROFILE_OPTIONS = OPTIONS

    def __init__(self, limits: Limits, url: str, clock=None, dist_conv: float = DIST_CONV,
                 angle_conv: float = ANGLE_CONV, *, baud: int = BAUD,
                 initial_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
                 lockstep: LockStep | None = None, open_timeout: float | None = 2.0, **options) -> None:
        super().__init__(limits)
        unknown = sorted(set(options) - set(OPTIONS))
        if unknown:
            raise ProfileError(f"rflex base: unknown option(s) {', '.join(unknown)}; "
                               f"allowed: {', '.join(OPTIONS)}")
        for name, value in (("dist_conv", dist_conv), ("angle_conv", angle_conv)):
            if not (isinstance(value, (int, float)) and 1.0 <= value <= 1e7):
                raise ProfileError(f"rflex base: {name} = {value!r}; allowed 1 .. 1e7 units")
        self.url = url
        self.clock = clock
        self.dist_conv = float(dist_conv)
        self.angle_conv = float(angle_conv)
        self.baud = int(baud)
        self.accel = float(options.get("accel", limits.max_accel))
        self.fault_reset = FaultReset(bool(options.get("reset_faults", False)), WATCHDOG_TIMEOUT)
        self.lockstep = lockstep
        self.open_timeout = open_timeout
        self.frame_gap = 0.0 if lockstep is not None else FRAME_GAP
        self.parser = p.FrameParser(gap_timeout=None if lockstep is not None else 0.1)
        self.backoff = Backoff(initial=0.1, maximum=2.0)
        self.watchdog = CommandWatchdog(WATCHDOG_TIMEOUT, self._watchdog_expired, "rflex-watchdog",
                                        time_source=self._now)
        self._emulator = None                 # set by for_simulation, closed with us
        self._port: serial.SerialBase | None = None
        self._state_lock = threading.Lock()
        self._write_lock = threading.RLock()
        self._report_cond = threading.Condition(self._state_lock)
        self._thread: threading.Thread | None = None
        self._dropped_readings = 0
        self._dropped_reason = ""
        self._running = False
        self._opened = False
        self._closed = False
        self._cmd = (0.0, 0.0)
        self._next_send = 0.0
        self._last_sent: tuple[float, float] | None = None
        self._commanded_at = -math.inf        # when a caller's command() last sent
        self._next_attempt = 0.0
        self._last_start = -math.inf
        self._cycles = 0
        self._next_status = 0.0
        # What the reports said.
        self._x, self._y, self._th = (float(c) for c in initial_pose)
        self._v = self._w = 0.0
        self._positions: list[int | None] = [None, None]
        self._baseline: tuple[int, int] | None = None
        self._fresh = 0
        self._sonar = [math.inf] * p.SONAR_COUNT
        self._panels: dict[int, int] = {}
        self._battery = math.nan
        self._brake = True
        self.drive_fault: dict | None = None  # device, code, meaning: latched until reset
        self.closing_note = ""                # a stop that closing could not deliver
        self._report_t = -math.inf
        self._reports = 0
        self._decode_errors = 0
        self._reconnects = 0

    # -- construction from a profile -------------------------------------------------------------
    @classmethod
    def profile_problems(cls, options: dict) -> list[tuple[str, str]]:
        found = [(key, f"unknown rflex option {key!r}; allowed: {', '.join(OPTIONS)}")
                 for key in options if key not in OPTIONS]
        for key in ("dist_conv", "angle_conv"):
            value = options.get(key, 1.0)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 1.0 <= value <= 1e7:
                found.append((key, f"{key} = {value!r}; allowed 1 .. 1e7 units"))
        if not isinstance(options.get("reset_faults", False), bool):
            found.append(("reset_faults", f"reset_faults = {options['reset_faults']!r} must be true or false"))
        return found

    @classmethod
    def for_profile(cls, profile, url: str, clock=None) -> "RFlexBase":
        """A driver for a real B21r at `url`: baud and factors from the profile's [base] table."""
        return cls(profile.limits, url, clock=clock, baud=profile.base.baud, **profile.base.options)

    # -- construction for the simulated world ---------------------------------------------------
    @classmethod
    def for_simulation(cls, profile, simulation, clock) -> "RFlexBase":
        """The real driver on a raw pty to an emulator around `simulation.world`. On a simulated
        clock both run in lock-step (deterministic); in real time the emulator still steps with
        the simulation and the driver runs its own threads."""
        from robots.rflex.emulator import RFlexEmulator

        options = dict(profile.base.options)
        dist = options.pop("dist_conv", DIST_CONV)
        angle = options.pop("angle_conv", ANGLE_CONV)
        lockstep = LockStep() if getattr(clock, "simulated", False) else None
        emulator = RFlexEmulator(simulation.world, dist_conv=dist, angle_conv=angle, clock=clock,
                                 lockstep=lockstep)
        emulator.attach(simulation)
        path = emulator.serve_pty()
        body = simulation.world.body
        # Reports come as the tick loop steps the world, which starts after open(): don't wait.
        base = cls(profile.limits, path, clock=clock, dist_conv=dist, angle_conv=angle,
                   initial_pose=(body.x, body.y, body.th), lockstep=lockstep, open_timeout=None,
                   **options)
        base._emulator = emulator
        return base

    # -- Base interface -------------------------------------------------------------------------
    def open(self) -> None:
        """Open the port and run the start sequence. In real time, wait for the first reports
        of both axes (LinkError after `open_timeout`, unless it is None); in lock-step they
        come with `poll()`."""
        if self._closed:
            raise LinkError(f"rflex base on {self.url} was closed; make a new one")
        if self._opened:
            return
        self._connect()
        self._opened = True
        if self.lockstep is not None:
            return
        self._running = True
        self._thread = threading.Thread(target=self._io_loop, name="rflex-io", daemon=True)
        self._thread.start()
        self.watchdog.start()
        if self.open_timeout is not None and not self.wait_for_report(self.open_timeout, both_axes=True):
            self.close()
            raise LinkError(f"no motor reports from an rFLEX controller on {self.url} within "
                            f"{self.open_timeout} s; is the base powered, and the line {self.baud} 8N1?")

    def read_state(self) -> BaseState:
        with self._state_lock:
            now = self._now()
            link_up = self._port is not None and now - self._report_t <= LINK_TIMEOUT
            fault = self.drive_fault or {}
            bumpers = 0
            for address, data in self._panels.items():
                panel = address - p.BUMPER_FIRST_ADDRESS
                if 0 <= panel < p.BUMPER_PANELS and data & 0xF:
                    bumpers |= 1 << panel
            return BaseState(
                t=self._report_t if self._report_t > -math.inf else now,
                x=self._x, y=self._y, th=self._th, v=self._v, w=self._w,
                sonar=tuple(self._sonar), bumpers=bumpers, stalled=False,
                motors_enabled=link_up and not self._brake, battery=self._battery,
                link_up=link_up and not fault,
                extra={"reports": self._reports, "reconnects": self._reconnects,
                       "watchdog_expirations": self.watchdog.expirations,
                       "decode_errors": self._decode_errors,
                       "parser": self.parser.stats, "command": self._cmd,
                       "dropped_readings": self._dropped_readings,
                       "dropped_reason": self._dropped_reason,
                       "link_error": (f"{fault['device']}: {fault['meaning']}" if fault else
                                      "port closed" if self._port is None else
                                      "no report yet" if self._report_t == -math.inf else
                                      f"no report for {now - self._report_t:.2f} s "
                                      f"(allowed {LINK_TIMEOUT:.2f} s)"),
                       "link_device": self.link_device,
                       **({"fault": f"{fault['device']}: {fault['meaning']}",
                           "fault_device": fault["device"], "fault_code": fault["code"],
                           "fault_meaning": fault["meaning"],
                           "fault_resettable": self._resettable(now, link_up)} if fault else {})})

    @property
    def link_device(self) -> str:
        """What a link episode is about: the controller and where it is."""
        return f"rFLEX controller on {self.url}"

    def command(self, v: float, w: float) -> None:
        """Clamp (NaN -> 0), remember, and send both axes now; the watchdog is re-armed."""
        if not self._opened or self._closed:
            raise LinkError(f"rflex base on {self.url} is not open; call open() first")
        self.fault_reset.note_command(*clamp_velocity(v, w, self.limits), self._now())
        if self._port is None or self.drive_fault is not None:
            return                             # link down or a drive fault: nothing is kept
        self.watchdog.feed()                   # the caller is alive (as P2OS: fed while down)
        if self._now() - self._report_t > LINK_TIMEOUT:
            return                             # reports stale: the stale-link stop holds
        v, w = clamp_velocity(v, w, self.limits)
        with self._state_lock:
            self._cmd = (v, w)
        self._commanded_at = self._now()
        self._send_axes(force=False)

    def stop(self) -> None:
        with self._state_lock:
            self._cmd = (0.0, 0.0)
        self.fault_reset.note_command(0.0, 0.0, self._now())
        self.watchdog.disarm()
        if self._opened and not self._closed:
            self._send_axes()

    def close(self) -> None:
        """Zero, stop sequence, brake on, release the port; then the emulator if we made one."""
        if self._closed:
            return
        self._closed = True
        self._running = False
        self.watchdog.stop()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=2.0)
        silent = self._now() - self._report_t
        if self._port is not None:
            with self._state_lock:
                self._cmd = (0.0, 0.0)
            try:
                self._send_frames(self._axis_frames(0.0, 0.0) + self._stop_frames())
                if self._opened and silent > LINK_TIMEOUT:
                    self.closing_note = (f"the stop went out to a controller silent for "
                                         f"{silent:.2f} s; it may not have arrived (the "
                                         f"controller's failsafe stops the robot)")
            except LinkError as exc:
                self.closing_note = (f"the stop could not be sent ({exc}); the controller's "
                                     f"failsafe stops the robot")
            self._drop_port()
        elif self._opened:
            self.closing_note = ("no stop could be sent, the port was closed (link down); the "
                                 "controller's failsafe stops the robot")
        if self._emulator is not None:
            self._emulator.close()

    def poll(self, timeout: float = 0.0) -> None:
        """Lock-step: take the emulator's reports of this sim time, then watchdog and resend."""
        if self.lockstep is None or not self._opened or self._closed:
            return
        now = self._now()
        if self._port is None:
            self._try_reconnect(now)
            return
        self._drain_lockstep()
        self._housekeeping(now)

    @property
    def report_count(self) -> int:
        """Motor reports decoded so far (for `wait_for_report(after=...)`)."""
        return self._reports

    def wait_for_report(self, timeout: float, both_axes: bool = False,
                        after: int | None = None) -> bool:
        """Real time: block until a motor report newer than number `after` (default: now)
        arrives, and with `both_axes` until odometry has both axes; False on timeout."""
        deadline = time.monotonic() + timeout
        with self._report_cond:
            seen = self._reports if after is None else after
            while True:
                if self._reports > seen and (not both_axes or self._baseline is not None):
                    return True
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return False
                self._report_cond.wait(remaining)

    # -- I/O ------------------------------------------------------------------------------------
    def _now(self) -> float:
        return self.clock.now() if self.clock is not None else time.monotonic()

    def _connect(self) -> None:
        port = open_serial(self.url, "the rFLEX port", baudrate=self.baud, bytesize=8,
                           parity="N", stopbits=1, xonxoff=False, rtscts=False,
                           timeout=0.02 if self.lockstep is None else 0)
        self.parser.reset()
        if self.lockstep is not None:
            self.lockstep.reset()
        self._port = port
        self._start_sequence(self._now())

    def _start_sequence(self, now: float) -> None:
        """Reports on, defaults, brake off, zero on both axes, sonar on, status (rflex.md §7)."""
        self._last_start = now
        with self._state_lock:
            self._positions = [None, None]
            self._baseline = None
            self._fresh = 0
        release = [] if self.drive_fault is not None else [p.brake_release()]   # held after a fault
        frames = [p.system_report_request(p.REPORT_PERIOD_US, 3), p.dio_reports_request(p.REPORT_PERIOD_US),
                  p.set_defaults(), *release]
        frames += self._axis_frames(0.0, 0.0)
        frames += [p.sonar_run(True), p.system_status_request()]
        self._send_frames(frames)
        self._brake = not release
        self._last_sent = (0.0, 0.0)
        self._next_send = now + RESEND_PERIOD

    @staticmethod
    def _stop_frames() -> list[p.Frame]:
        return [p.set_defaults(), p.system_report_request(0, 0), p.dio_reports_request(0),
                p.sonar_run(False), p.ir_run(False), p.brake_set()]

    def _axis_frames(self, v: float, w: float) -> list[p.Frame]:
        """Translation then rotation, magnitudes with a direction byte (Player's constants)."""
        return [p.axis_set_dir(p.TRANSLATION_AXIS, p.velocity_units(v, self.dist_conv),
                               p.velocity_units(self.accel, self.dist_conv), p.TRANSLATION_TORQUE),
                p.axis_set_dir(p.ROTATION_AXIS, p.velocity_units(w, self.angle_conv),
                               p.ROTATION_ACCEL, p.ROTATION_TORQUE)]

    def _send_axes(self, force: bool = True) -> None:
        """Both axes now. Unforced (a caller's repeat of the same command) only when the 10 Hz
        resend is due anyway, so a tick loop commanding every tick does not double the traffic."""
        with self._state_lock:
            command = self._cmd
        now = self._now()
        if not force and command == self._last_sent and now < self._next_send - 1e-6:
            return
        self._last_sent = command
        self._next_send = now + RESEND_PERIOD
        try:
            self._send_frames(self._axis_frames(*command))
        except LinkError:
            self._lost("write failed")

    def _send_frames(self, frames: list[p.Frame]) -> None:
        """Write frames; in real time with a gap after each, in lock-step as one write and then
        wait until the emulator has applied them."""
        chunks = [p.encode_raw(frame) for frame in frames]
        if not self.frame_gap:
            chunks = [b"".join(chunks)]
        with self._write_lock:
            port = self._port
            if port is None:
                return
            for raw in chunks:
                if self.lockstep is not None:
                    self.lockstep.to_device.wrote(len(raw))
                try:
                    port.write(raw)
                except (serial.SerialException, OSError) as exc:
                    raise LinkError(f"rFLEX port {self.url}: write failed: {exc}") from exc
                if self.frame_gap:
                    time.sleep(self.frame_gap)
            if self.lockstep is not None:      # the emulator applies it before we go on
                self.lockstep.deliver(LOCKSTEP_TIMEOUT)

    def _read_available(self) -> bytes:
        """All that has arrived (in real time waiting up to 20 ms for the first byte)."""
        port = self._port
        if port is None:
            return b""
        try:
            if self.lockstep is None:
                return read_arrived(port, 0.02)
            waiting = port.in_waiting
            return port.read(waiting) if waiting else b""
        except (serial.SerialException, OSError, TypeError) as exc:
            raise LinkError(f"rFLEX port {self.url}: read failed: {exc}") from exc

    def _drain_lockstep(self) -> None:
        counter = self.lockstep.to_host
        deadline = time.monotonic() + LOCKSTEP_TIMEOUT
        while True:
            try:
                data = self._read_available()
            except LinkError:
                self._lost("read failed")
                return
            if data:
                counter.got(len(data))
                self._handle_bytes(data)
            elif counter.backlog() <= 0 or time.monotonic() > deadline:
                return
            else:
                self._wait_readable(min(0.02, max(0.0, deadline - time.monotonic())))

    def _wait_readable(self, timeout: float) -> None:
        """Lock-step: sleep until the emulator's bytes are readable (a pty hands them over a
        little later than they were written), not in fixed slices that each overshoot."""
        port = self._port
        try:
            select.select([port.fileno()], [], [], timeout)
        except (AttributeError, OSError, ValueError, io.UnsupportedOperation):
            time.sleep(0.0002)               # a port without a descriptor (a URL handler)

    def _io_loop(self) -> None:
        while self._running:
            now = self._now()
            if self._port is None:
                self._try_reconnect(now)
                time.sleep(0.01)
                continue
            try:
                data = self._read_available()
            except LinkError:
                self._lost("read failed")
                continue
            if data:
                self._handle_bytes(data, time.monotonic())
            self._housekeeping(self._now())

    def _housekeeping(self, now: float) -> None:
        """Watchdog (lock-step), the 10 Hz resend, the silent-controller restart. The resend
        waits while a caller commands every tick: in lock-step the tick's command follows at
        the same instant, and a resend of the last tick's command went out just before it,
        out of date in most ticks (rflex.md §8: not back to back)."""
        if self.lockstep is not None:
            self.watchdog.check(now)
        if self.fault_reset.expired(now):
            with self._state_lock:
                self.fault_reset.refuse(now, "no status report after MOT_BRAKE_RELEASE")
        if now - self._report_t > LINK_TIMEOUT:
            if self._cmd != (0.0, 0.0):
                self._stale_stop()
            if now - self._last_start >= RESTART_PERIOD:
                self._silent(now)
        if now >= self._next_send - 1e-6 and now - self._commanded_at >= CALLER_RESENDS:
            self._cycles += 1
            self._send_axes()
        if now >= self._next_status and self._port is not None:
            self._next_status = now + STATUS_PERIOD
            self._send_frames_safely([p.system_status_request()])

    def _stale_stop(self) -> None:
        """Reports stopped: zero now, while the line may still carry it (a silent controller
        would otherwise run on until its failsafe); commands are kept out until reports
        come again, and nothing resumes by itself."""
        with self._state_lock:
            self._cmd = (0.0, 0.0)
        self._send_axes()

    def _send_frames_safely(self, frames: list[p.Frame]) -> None:
        try:
            self._send_frames(frames)
        except LinkError:
            self._lost("write failed")

    def _silent(self, now: float) -> None:
        """No reports: forget the command (nothing resumes by itself) and restart the controller
        side in case it was power-cycled."""
        with self._state_lock:
            self._cmd = (0.0, 0.0)
        self.watchdog.disarm()
        try:
            self._start_sequence(now)
        except LinkError:
            self._lost("write failed")

    def _lost(self, why: str) -> None:
        """The port failed: zero the command, close, and let the reconnect loop try again."""
        with self._state_lock:
            self._cmd = (0.0, 0.0)
        self.watchdog.disarm()
        self._drop_port()
        self._next_attempt = self._now() + self.backoff.next_delay()

    def _drop_port(self) -> None:
        with self._write_lock:
            port, self._port = self._port, None
        if port is not None:
            try:
                port.close()
            except (serial.SerialException, OSError):
                pass

    def _try_reconnect(self, now: float) -> None:
        if now < self._next_attempt or self._closed:
            return
        try:
            self._connect()
        except LinkError:
            self._drop_port()
            self._next_attempt = now + self.backoff.next_delay()
            return
        self.backoff.reset()
        self._reconnects += 1

    # -- reports --------------------------------------------------------------------------------
    def _handle_bytes(self, data: bytes, wall: float | None = None) -> None:
        """Decode what arrived; in real time (`wall` given) only the newest FLOOD_KEEP bytes of
        a flood (robots.link.arrival), and every report is stamped with the time it was read,
        so the newest report's age is the age of its arrival."""
        arrived = self._now()
        frames = (self.parser.feed(data) if wall is None else
                  self.parser.feed_newest(data, FLOOD_KEEP, wall))
        for frame in frames:
            try:
                report = p.decode_report(frame)
            except ProtocolError:
                self._decode_errors += 1
                continue
            self._apply_report(report, arrived)

    def _apply_report(self, report, arrived: float | None = None) -> None:
        with self._report_cond:
            if isinstance(report, p.MotorReport):
                self._motor(report)
                self._report_t = self._now() if arrived is None else arrived
                self._reports += 1
                self._report_cond.notify_all()
            elif isinstance(report, p.SonarReport):
                self._apply_sonar(report.readings)
            elif isinstance(report, p.DioReport):
                self._panels[report.address] = report.data
            elif isinstance(report, p.SystemStatus):
                self._battery = report.volts
                if report.brake and not self._brake:
                    self._brake_set_by_itself()
                self._brake = bool(report.brake)
                self._judge_reset(bool(report.brake))

    def _apply_sonar(self, readings: tuple[tuple[int, int], ...]) -> None:
        """Each reading to its sonar; the whole ring in profile order (what the controller
        sends) in one pass."""
        if len(readings) == p.SONAR_COUNT:
            wires, raws = zip(*readings)
            if wires == p.SONAR_WIRE_IDS:
                self._sonar[:] = [p.sonar_metres(raw) for raw in raws]
                return
        for wire, raw in readings:
            index = p.SONAR_INDEX_OF_WIRE_ID.get(wire)
            if index is None:          # not a sonar of the B21r ring: counted, dropped
                self._dropped_readings += 1
                self._dropped_reason = f"sonar wire id {wire}: not on the B21r's ring"
            else:
                self._sonar[index] = p.sonar_metres(raw)

    def _motor(self, report: p.MotorReport) -> None:
        """Keep each axis; integrate once both are fresh (ROS's odomReady mask)."""
        if report.axis not in (p.TRANSLATION_AXIS, p.ROTATION_AXIS):
            return
        self._positions[report.axis] = report.position
        if report.axis == p.TRANSLATION_AXIS:
            self._v = report.velocity / self.dist_conv
        else:
            self._w = report.velocity / self.angle_conv
        self._fresh |= 1 << report.axis
        if self._fresh != 3:
            return
        self._fresh = 0
        current = (self._positions[0], self._positions[1])
        if self._baseline is not None:
            distance = p.wrap_delta(current[0], self._baseline[0]) / self.dist_conv
            turn = p.wrap_delta(current[1], self._baseline[1]) / self.angle_conv
            heading = self._th + turn / 2
            self._x += distance * math.cos(heading)
            self._y += distance * math.sin(heading)
            self._th = math.atan2(math.sin(self._th + turn), math.cos(self._th + turn))
        self._baseline = current

    def _brake_set_by_itself(self) -> None:
        """The controller reports its brake set though we released it (the e-stop or the
        motor power): a drive fault. Zero, hold still, say which and why (issue 24)."""
        if self.drive_fault is not None:
            return
        self.drive_fault = {"device": "rFLEX brake", "code": None,
                            "meaning": "brake set by the controller after MOT_BRAKE_RELEASE "
                                       "(SYS_STATUS brake = 1: e-stop or motor power off?)"}
        self._cmd = (0.0, 0.0)               # (the caller holds the state lock)
        self.watchdog.disarm()

    # -- fault reset ----------------------------------------------------------------------------
    def _resettable(self, now: float, link_up: bool) -> bool:
        return self.drive_fault is not None and link_up and self.fault_reset.may_try(now)

    def fault_resettable(self) -> bool:
        """A latched fault `reset_faults()` would act on now: the option is on, reports come,
        no motion is commanded, no attempt is waiting or was just refused."""
        now = self._now()
        return self._resettable(now, self._port is not None and now - self._report_t <= LINK_TIMEOUT)

    def reset_faults(self) -> list[str]:
        """Release the brake after a drive fault (rFLEX: zero on both axes, MOT_BRAKE_RELEASE,
        then SYS_STATUS to confirm). An explicit act, never automatic; refused
        (FaultResetError) while motion is commanded, with the link down, or without the option
        `reset_faults`. The fault clears when the status reports the brake released; if the
        controller keeps it set (the e-stop still pressed) the fault stays. The command stays
        zero until the next `command()`. Returns the devices a reset was sent for."""
        now = self._now()
        where = f"{self.url}: rFLEX brake"
        self.fault_reset.refuse_unless_allowed(now, where)
        if self.drive_fault is None:
            return []
        if self._port is None or now - self._report_t > LINK_TIMEOUT:
            raise FaultResetError(f"{where}: fault reset refused: the controller is not reporting")
        device = self.drive_fault["device"]     # the reply may clear it before we return
        with self._state_lock:
            self._cmd = (0.0, 0.0)
        self.watchdog.disarm()
        self.fault_reset.start(now)
        try:
            self._send_frames(self._axis_frames(0.0, 0.0) +
                              [p.brake_release(), p.system_status_request()])
        except LinkError as exc:
            self.fault_reset.refuse(now, f"the release could not be sent ({exc})")
            self._lost("write failed")
            raise FaultResetError(f"{where}: fault reset: the release could not be sent ({exc})") from exc
        self._last_sent = (0.0, 0.0)
        self._next_send = now + RESEND_PERIOD
        return [device]

    def _judge_reset(self, brake: bool) -> None:
        """A status report while a reset waits: brake released clears the fault, brake set
        means the controller kept it (the caller holds the state lock)."""
        now = self._now()
        if self.fault_reset.pending_since is None:
            return
        if brake:
            self.fault_reset.refuse(now, "the controller kept its brake set after "
                                         "MOT_BRAKE_RELEASE (the e-stop still pressed?)")
        elif self.fault_reset.confirm():
            self.drive_fault = None
            self._cmd = (0.0, 0.0)

    def _watchdog_expired(self) -> None:
        with self._state_lock:
            self._cmd = (0.0, 0.0)
        if self._port is not None:
            self._send_axes()

