"""The P2OS base driver: a Pioneer 2 (or the emulator) behind any pyserial URL.

`P2OSBase(limits, url)` opens `/dev/ttyS0`, `socket://host:port` or a pty path. `open()` runs the
handshake (SYNC0/1/2 with retries, the baud rates in Player's order, CLOSE-and-retry when the
robot is still open from an earlier client), picks the conversion factors from the SYNC2
subclass, then sends OPEN, zero velocity, ENABLE 1 and SONAR 1.

Safety, in real time:
- `command(v, w)` clamps to the profile's limits (NaN/inf become 0) and sends VEL+RVEL when the
  command changes, and again every KEEPALIVE s while the same command keeps coming: the
  keep-alive is tied to fresh commands, never a free-standing pulse.
- A watchdog thread sends zero WATCHDOG s (0.15) after the last `command()`, whatever the
  caller is doing. Nothing is re-sent after that until a new `command()`.
- A reader thread decodes SIPs; no SIP for 3 cycles means the link is down. It sends zero on
  the way out (the line may still carry it), then reconnects with back-off, and on success sends
  zero before ENABLE; the old command is forgotten. The state says why the link went down
  (`extra["link_error"]`); the log says it once per episode, and again when it is back.
- The reader takes everything that has arrived in one call and decodes only the newest
  FLOOD_KEEP bytes of a flood (`robots.link.arrival`); a SIP's age is the age of its arrival,
  so silence after a flood is noticed as soon as silence after nothing.
- Motors that go off after they were on (SIP FLAGS bit 0 clear), or the e-stop bit 5 from the
  first SIP on (a robot started with its e-stop pressed), are a drive fault: zero at once,
  commands ignored, `link_up` False and `extra["fault_device"]`, `fault_code`,
  `fault_meaning` for the trace's `fault` event, until the driver is closed, or until `reset_faults()` (with the option `reset_faults`): ENABLE 1 once the e-stop is
  released and no motion is commanded; the fault clears when a SIP shows the motors on
  (`robots.link.fault_reset`), and the command stays zero until the next `command()`.
- A reading the profile does not describe (a sonar number beyond the profile's ring, a range
  beyond twice the sensor's reach) is dropped and counted (`extra["dropped_readings"]`, with
  the newest reason in `extra["dropped_reason"]`), never passed up.

On a simulated clock (`for_simulation` with `clock.simulated`) there are no driver threads:
`poll()` (called by the tick loop right after `simulation.advance`) reads until every byte the
emulator wrote has been decoded, and checks link liveness and the command watchdog in sim time.
Each write waits until the emulator has acted on it (`robots.link.LockStep`), so commands take
effect in the next step and the run is deterministic. The handshake needs no clock at all.
There the driver does not reconnect: the emulator lives in the same process, so a dead link
means a broken run, reported as `link_up=False` (the safety arbiter then keeps the robot still).
"""
from __future__ import annotations

import logging
import math
import threading
import time
from dataclasses import replace

import serial

from robots.base import Base, BaseState, clamp_velocity
from robots.exceptions import FaultResetError, HandshakeError, LinkError
from robots.link.arrival import read_arrived
from robots.link.backoff import Backoff
from robots.link.fault_reset import FaultReset
from robots.link.lockstep import LockStep
from robots.link.port import open_serial
from robots.link.watchdog import CommandWatchdog
from robots.p2os import protocol as p
from robots.profile import Limits

log = logging.getLogger(__name__)

BAUDS = (9600, 38400, 19200, 115200, 57600)   # Player's order
SIP_CYCLE = 0.1            # s
MISSED_CYCLES = 3          # link down after this many SIP cycles without one
WATCHDOG = 0.15            # s without a fresh command -> zero (the bound we promise is 0.2 s)
KEEPALIVE = 0.5            # s, re-send an unchanged fresh command this often (ARIA's figure)
READ_QUANTUM = 0.02        # s, longest a read blocks (so close() and liveness stay prompt)
FLOOD_KEEP = 16384         # bytes of one read parsed at most (~300 SIPs): the newest of a flood
STILL_OPEN, NO_REPLY = "still open", "no reply"
ESTOP_FLAG = 0x20          # SIP FLAGS bit 5: e-stop (ARIA, later firmware)


class _Port:
    """The serial port, counting bytes for lock-step when an in-process emulator is on the other end."""

    def __init__(self, port: serial.SerialBase, lockstep: LockStep | None) -> None:
        self.serial = port
        self.lockstep = lockstep

    def write(self, data: bytes) -> None:
        if self.lockstep is not None:
            self.lockstep.to_device.wrote(len(data))
        self.serial.write(data)
        if self.lockstep is not None:
            self.lockstep.deliver(2.0)

    def read(self, timeout: float) -> bytes:
        """All that has arrived, or wait up to `timeout` s for at least one byte."""
        data = read_arrived(self.serial, timeout)
        if data and self.lockstep is not None:
            self.lockstep.to_host.got(len(data))
        return data

    def close(self) -> None:
        try:
            self.serial.close()
        except Exception:
            pass


class P2OSBase(Base):
    """A Pioneer 2 base over P2OS. Options: baud, retries, reply_timeout, sonar_max_range,
    watchdog, sonar (on at connect), sonar_count (the profile's ring; more are dropped),
    reconnect (bool), reset_faults (allow `reset_faults()`), lockstep (in-process emulator only)."""

    PROFILE_OPTIONS = ("subclass", "reset_faults")

    def __init__(self, limits: Limits, url: str, subclass_hint: str | None = "p2dx", clock=None,
                 **options) -> None:
        super().__init__(limits)
        self.url = url
        self.subclass_hint = options.pop("subclass", None) or subclass_hint or "p2dx"
        self.clock = clock
        self.simulated = bool(getattr(clock, "simulated", False))
        self.baud = int(options.pop("baud", 9600))
        self.retries = int(options.pop("retries", 3))
        self.reply_timeout = float(options.pop("reply_timeout", 0.3))
        self.sonar_max_range = options.pop("sonar_max_range", None)
        self.sonar_count = options.pop("sonar_count", None)
        self.sonar_at_connect = bool(options.pop("sonar", True))
        self.reconnect = bool(options.pop("reconnect", True))
        self.lockstep: LockStep | None = options.pop("lockstep", None)
        self.watchdog = CommandWatchdog(float(options.pop("watchdog", WATCHDOG)), self._on_stale,
                                        name="p2os-watchdog", time_source=self._time)
        self.backoff = Backoff(initial=0.1, factor=2.0, maximum=2.0)
        self.fault_reset = FaultReset(bool(options.pop("reset_faults", False)), self.watchdog.timeout)
        self.options = options                      # unknown options are kept, not fatal
        self.factors = p.factors_for(self.subclass_hint) or p.FACTORS["p2dx"]
        self.robot_id: tuple[str, str, str] | None = None
        self.connected_baud: int | None = None
        self.parser = p.P2OSParser()
        self.odometry = p.Odometry(self.factors)
        self.stats = {"sips": 0, "watchdog_stops": 0, "reconnects": 0, "link_downs": 0,
                      "bad_sips": 0, "dropped_readings": 0}
        self.dropped_reason = ""
        self.emulator = None                        # set by for_simulation
        self._port: _Port | None = None
        self._lock = threading.RLock()              # guards writes and command state
        self._state_cond = threading.Condition()
        self._state = BaseState(t=self._now(), link_up=False)
        self._sonar: list[float] = [math.inf] * self._ring_size(self.factors)
        self._link_up = False
        self._closing = threading.Event()
        self._reader: threading.Thread | None = None
        self._cmd = (0, 0)                          # (mm/s, deg/s) last commanded
        self._sent: tuple[int, int] | None = None   # last sent, and when
        self._sent_at = -math.inf
        self._last_sip_t = -math.inf
        self._next_attempt = 0.0
        self.last_error = ""
        self._motors_seen = False                   # motors reported on since this connection
        self._opened_once = False                   # open() succeeded (so close() has a robot)
        self.closing_note = ""                      # a stop that closing could not deliver
        self.drive_fault: dict | None = None        # device, code, meaning: latched until reset
        self._estop = False                         # the newest SIP's e-stop bit

    # -- wiring -------------------------------------------------------------------------------------
    @classmethod
    def profile_problems(cls, options: dict) -> list[tuple[str, str]]:
        """A profile sets only `subclass` and `reset_faults` (the others are the driver's own)."""
        found = [(key, f"unknown p2os option {key!r}; allowed: {', '.join(cls.PROFILE_OPTIONS)}")
                 for key in options if key not in cls.PROFILE_OPTIONS]
        if "subclass" in options and not isinstance(options["subclass"], str):
            found.append(("subclass", f"subclass = {options['subclass']!r} must be a name such as \"p2dx\""))
        if not isinstance(options.get("reset_faults", False), bool):
            found.append(("reset_faults", f"reset_faults = {options['reset_faults']!r} must be true or false"))
        return found

    @classmethod
    def for_profile(cls, profile, url: str, clock=None) -> "P2OSBase":
        """A driver for a real Pioneer at `url`, configured from the robot profile."""
        max_range = profile.sonar.max_range if profile.sonar is not None else None
        return cls(profile.limits, url, subclass_hint=profile.base.options.get("subclass"),
                   clock=clock, sonar_max_range=max_range, sonar_count=_sonar_count(profile),
                   baud=profile.base.baud,
                   reset_faults=profile.base.options.get("reset_faults", False))

    @classmethod
    def for_simulation(cls, profile, simulation, clock) -> "P2OSBase":
        """Start the firmware emulator on a pty around `simulation.world`; a driver for that pty."""
        from robots.p2os.emulator import P2OSEmulator   # emulator only when simulating
        lockstep = LockStep() if getattr(clock, "simulated", False) else None
        emulator = P2OSEmulator.for_profile(profile, simulation.world, clock=clock,
                                            lockstep=lockstep)
        emulator.attach(simulation)
        path = emulator.serve_pty()
        if lockstep is None:
            emulator.start_clock()
        max_range = profile.sonar.max_range if profile.sonar is not None else None
        base = cls(profile.limits, path, subclass_hint=profile.base.options.get("subclass"),
                   clock=clock, sonar_max_range=max_range, sonar_count=_sonar_count(profile),
                   lockstep=lockstep, reconnect=lockstep is None,
                   reset_faults=profile.base.options.get("reset_faults", False))
        base.emulator = emulator
        return base

    # -- time ---------------------------------------------------------------------------------
    def _now(self) -> float:
        """Robot time for state stamps (the clock the hardware was opened with)."""
        return self.clock.now() if self.clock is not None else time.monotonic()

    def _time(self) -> float:
        """Time for watchdog, keep-alive and liveness: sim time in lock-step, else monotonic."""
        return self.clock.now() if self.simulated else time.monotonic()

    # -- Base interface ---------------------------------------------------------------------------
    def open(self) -> None:
        self._closing.clear()
        self._connect()
        self._opened_once = True
        self._last_sip_t = self._time()
        if not self.simulated:
            self._wait_first_sip()
            self.watchdog.start()
            self._reader = threading.Thread(target=self._read_loop, name="p2os-reader", daemon=True)
            self._reader.start()

    def read_state(self) -> BaseState:
        return self._state

    def command(self, v: float, w: float) -> None:
        v, w = clamp_velocity(v, w, self.limits)
        mm = _toward_zero_within(v * 1000.0, self.limits.max_speed * 1000.0)
        deg = _toward_zero_within(math.degrees(w), math.degrees(self.limits.max_turn_rate))
        with self._lock:
            now = self._time()
            self.watchdog.feed(now)
            self.fault_reset.note_command(v, w, now)
            if self.drive_fault is not None:
                return                     # a drive fault holds still until the run ends
            self._cmd = (mm, deg)
            if not self._link_up:
                return
            if self._sent != (mm, deg) or now - self._sent_at >= KEEPALIVE:
                self._send_velocity(mm, deg, now)

    def stop(self) -> None:
        with self._lock:
            self._cmd = (0, 0)
            self.fault_reset.note_command(0.0, 0.0, self._time())
            self.watchdog.disarm()
            if self._link_up:
                self._send_velocity(0, 0, self._time())

    def close(self) -> None:
        if self._closing.is_set() and self._port is None:
            return
        self._closing.set()
        self.watchdog.stop()
        if self._reader is not None and self._reader is not threading.current_thread():
            self._reader.join(timeout=2.0)
        self._reader = None
        with self._lock:
            if self._port is not None and self._link_up:
                try:
                    self._port.write(p.vel(0) + p.rvel(0))
                    self._port.write(p.close())
                except Exception as exc:
                    self.closing_note = (f"the stop and CLOSE could not be sent ({exc}); the "
                                         f"controller's own watchdog stops the robot")
            elif self._opened_once:
                why = self._state.extra.get("link_error") or "the link was down"
                self.closing_note = (f"no stop could be sent, the link was down ({why}); the "
                                     f"controller's own watchdog stops the robot")
            self._drop_port()
            self._set_link(False)
        if self.emulator is not None:
            self.emulator.close()
            self.emulator = None

    def poll(self, timeout: float = 0.0) -> None:
        """Lock-step: decode everything the emulator wrote; check liveness and watchdog in sim time."""
        if not self.simulated:
            return
        now = self._time()
        if not self._link_up:
            self._try_reconnect(now)
            return
        self._drain(deadline=time.monotonic() + max(timeout, 2.0))
        self.watchdog.check(now)
        self._check_liveness(now)

    # -- connection ---------------------------------------------------------------------------------
    def _connect(self) -> None:
        """Open the port, handshake, OPEN, zero, ENABLE, sonar. Raises LinkError/HandshakeError."""
        self._drop_port()
        raw = open_serial(self.url, "the port", baudrate=self.baud, timeout=self.reply_timeout,
                          write_timeout=1.0)
        if self.lockstep is not None:
            self.lockstep.reset()
        port = _Port(raw, self.lockstep)
        try:
            name, klass, subclass, baud = self._handshake(port)
            factors = p.factors_for(subclass)
            if factors is None:
                log.warning("%s: unknown subclass %r; using %s factors", self.url, subclass,
                            self.factors.subclass)
                factors = p.factors_for(self.subclass_hint) or self.factors
            port.write(p.open_())
            port.write(p.vel(0) + p.rvel(0))          # zero before the motors come on
            port.write(p.setv(round(self.limits.max_speed * 1000.0)) +
                       p.setrv(max(1, round(math.degrees(self.limits.max_turn_rate)))))
            port.write(p.enable(True))
            port.write(p.sonar(self.sonar_at_connect))
        except (serial.SerialException, OSError) as exc:
            port.close()
            raise LinkError(f"{self.url}: link failed during connection: {exc}") from exc
        except Exception:
            port.close()
            raise
        with self._lock:
            self._port = port
            self.robot_id = (name, klass, subclass)
            self.connected_baud = baud
            if factors is not self.factors:
                self.factors = factors
                self._sonar = [math.inf] * self._ring_size(factors)
            self.odometry = p.Odometry(self.factors)
            self.parser.reset()
            self._cmd = (0, 0)                       # nothing resumes by itself
            self._motors_seen = False
            self._sent, self._sent_at = (0, 0), self._time()
            self._last_sip_t = self._time()
            self._set_link(True)
        log.info("%s: connected to %s %s %s at %d baud", self.url, name, klass, subclass, baud)

    def _handshake(self, port: _Port) -> tuple[str, str, str, int]:
        bauds = [self.baud] + [b for b in BAUDS if b != self.baud]
        heard = []
        for baud in bauds:
            port.serial.baudrate = baud
            for _ in range(self.retries):
                if self._closing.is_set():
                    raise LinkError(f"{self.url}: closed during the handshake")
                result = self._sync(port)
                if isinstance(result, tuple):
                    return (*result, baud)
                heard.append(f"{baud}: {result}")
                port.write(p.close())                # ARIA: CLOSE when no reply or still open
                if result == STILL_OPEN:
                    time.sleep(2 * SIP_CYCLE)
                port.serial.reset_input_buffer()
        raise HandshakeError(
            f"{self.url}: no P2OS handshake (expected echoes of SYNC0/SYNC1 and a SYNC2 reply "
            f"with name, class, subclass; tried {', '.join(map(str, bauds))} baud, "
            f"{self.retries} times each; got: {'; '.join(heard[-3:])}). Is the robot on and "
            f"the cable in this port?")

    def _sync(self, port: _Port):
        """One SYNC0-1-2 pass: (name, class, subclass), or STILL_OPEN / a reason string."""
        port.serial.reset_input_buffer()
        parser = p.P2OSParser()
        for stage in (0, 1, 2):
            port.write(p.command(stage))
            reply = self._await(port, parser, stage)
            if not isinstance(reply, p.Packet):
                return f"{reply} to SYNC{stage}"
        try:
            return p.parse_sync2(reply.data)
        except Exception as exc:
            return f"bad SYNC2 reply: {exc}"

    def _await(self, port: _Port, parser: p.P2OSParser, kind: int):
        """The reply of type `kind`, STILL_OPEN if a SIP came instead, or what came otherwise."""
        deadline = time.monotonic() + self.reply_timeout
        others = []
        while time.monotonic() < deadline:
            for packet in parser.feed(port.read(READ_QUANTUM)):
                if packet.kind == kind:
                    return packet
                if packet.kind in p.SIP_TYPES:
                    return STILL_OPEN
                others.append(f"{packet.kind:#04x}")
        if others:
            return f"packets of type {', '.join(others[:4])} instead of a reply"
        if parser.stats.dropped_bytes:
            return f"{NO_REPLY} ({parser.stats.dropped_bytes} bytes that formed no packet)"
        return NO_REPLY

    def _wait_first_sip(self) -> None:
        wait = (MISSED_CYCLES + 1) * SIP_CYCLE + 0.5
        deadline = time.monotonic() + wait
        while time.monotonic() < deadline and self.stats["sips"] == 0:
            self._read_once(READ_QUANTUM)
        if self.stats["sips"] == 0:
            self._drop_port()
            self._set_link(False)
            raise HandshakeError(f"{self.url}: handshake done but no SIP arrived after OPEN "
                                 f"within {wait:.1f} s; the controller did not start its servers")

    # -- receiving -----------------------------------------------------------------------------------
    def _read_loop(self) -> None:
        """Reader thread (real time): decode SIPs, watch liveness, reconnect when the link drops."""
        while not self._closing.is_set():
            if not self._link_up:
                if not self.reconnect:
                    self._closing.wait(0.1)
                    continue
                self._reconnect_with_backoff()
                continue
            try:
                self._read_once(READ_QUANTUM)
                self._check_liveness(self._time())
            except Exception as exc:             # never let the reader die with the link "up"
                log.debug("%s: reader failed", self.url, exc_info=True)
                self._link_lost(f"reader error: {type(exc).__name__}: {exc}")

    def _read_once(self, timeout: float) -> None:
        port = self._port
        if port is None:
            return
        try:
            data = port.read(timeout)
        except (serial.SerialException, OSError, TypeError, AttributeError) as exc:
            self._link_lost(f"port error: {exc}")
            return
        if data:
            self._decode(data, self._time())

    def _drain(self, deadline: float) -> None:
        """Lock-step: read until everything the emulator wrote has been decoded."""
        port = self._port
        while port is not None and self.lockstep.to_host.backlog() > 0:
            if time.monotonic() > deadline:
                self.last_error = "emulator bytes did not arrive in time"
                return
            self._read_once(READ_QUANTUM)
            port = self._port

    def _decode(self, data: bytes, arrived: float) -> None:
        """Decode what arrived at `arrived`; in real time only the newest FLOOD_KEEP bytes of
        a flood (robots.link.arrival), so a SIP's age is the age of its arrival."""
        # the silent-gap rule is about a real line: in lock-step a packet the pty hands over in
        # two pieces on a loaded machine is not a gap (dropping it made runs depend on the load)
        if self.lockstep is not None:
            packets = self.parser.feed(data)
        else:
            packets = self.parser.feed_newest(data, FLOOD_KEEP, time.monotonic())
        for packet in packets:
            if packet.kind in p.SIP_TYPES:
                try:
                    sip = p.decode_sip(packet)
                except Exception as exc:
                    self.stats["bad_sips"] += 1
                    self.last_error = str(exc)
                    continue
                self._on_sip(sip, arrived)

    def _on_sip(self, sip: p.SIP, arrived: float | None = None) -> None:
        f = self.factors
        x, y, th = self.odometry.update(sip)
        v, w = self.odometry.velocities(sip)
        for number, units in sip.sonar:
            metres = units * f.range / 1000.0
            if number >= len(self._sonar):
                self._drop(f"sonar number {number}: the profile has sonars 0..{len(self._sonar) - 1}")
                continue
            if self.sonar_max_range is not None and metres > 2 * self.sonar_max_range:
                self._drop(f"sonar {number} range {metres:.2f} m: beyond the sensor's reach of "
                           f"{self.sonar_max_range:g} m")
                continue
            if self.sonar_max_range is not None and metres >= self.sonar_max_range - 1e-9:
                metres = math.inf
            self._sonar[number] = metres
        bumpers = (1 if sip.front_bumpers else 0) | (2 if sip.rear_bumpers else 0)
        self._check_drive(sip)
        self._last_sip_t = self._time() if arrived is None else arrived
        self.stats["sips"] += 1
        state = BaseState(
            t=self._now(), x=x, y=y, th=th, v=v, w=w, sonar=tuple(self._sonar), bumpers=bumpers,
            stalled=sip.left_stall or sip.right_stall, motors_enabled=sip.motors_enabled,
            battery=sip.battery / 10.0, link_up=self.drive_fault is None,
            extra={"front_bumpers": sip.front_bumpers, "rear_bumpers": sip.rear_bumpers,
                   "estop": bool(sip.flags & 0x20), "sips": self.stats["sips"],
                   "subclass": self.factors.subclass,
                   "rejected_packets": self.parser.stats.rejected,
                   "dropped_bytes": self.parser.stats.dropped_bytes,
                   "dropped_readings": self.stats["dropped_readings"],
                   "dropped_reason": self.dropped_reason,
                   "link_device": self.link_device, **self._fault_extra()})
        with self._state_cond:
            self._state = state
            self._state_cond.notify_all()

    @property
    def link_device(self) -> str:
        """What a link episode is about: the controller and where it is."""
        return f"P2OS controller on {self.url}"

    def _check_drive(self, sip: p.SIP) -> None:
        """Motors that go off after they were on (the motor switch, the e-stop, the controller
        giving up) are a drive fault: stop, hold still, say which and why (issue 24). A reset
        waiting for its confirmation clears the fault when a SIP shows the motors on."""
        estop = bool(sip.flags & ESTOP_FLAG)
        self._estop = estop
        now = self._time()
        if sip.motors_enabled and not estop:
            self._motors_seen = True
            if self.drive_fault is not None and self.fault_reset.confirm():
                log.warning("%s: drive fault reset: the motors are on again (%s); zero until "
                            "the next command", self.url, self.drive_fault["meaning"])
                self.drive_fault = None
            return
        if self.fault_reset.expired(now):
            self.fault_reset.refuse(now, "the motors stayed off after ENABLE 1"
                                    + (" (e-stop pressed)" if estop else ""))
            log.warning("%s: drive fault reset did not take: %s", self.url,
                        self.fault_reset.last_failure)
        if (not self._motors_seen and not estop) or self.drive_fault is not None:
            return                         # still starting (ENABLE not yet in force), or known;
                                           # the e-stop bit is a fault from the first SIP on
        meaning = ("e-stop pressed (SIP FLAGS bit 5)" if estop else
                   "motors disabled by the controller (SIP FLAGS bit 0 clear: the motor switch, "
                   "the e-stop or a controller fault)")
        self.drive_fault = {"device": "P2OS motors", "code": sip.flags, "meaning": meaning}
        self.last_error = f"{self.url}: drive fault: {meaning}"
        log.warning("%s", self.last_error)
        with self._lock:
            self._cmd = (0, 0)
            self.watchdog.disarm()
            if self._link_up:
                self._send_velocity(0, 0, self._time())

    def fault_resettable(self) -> bool:
        """A latched fault `reset_faults()` would act on now: the option is on, the e-stop is
        released, no motion is commanded, no attempt is waiting or was just refused."""
        return (self.drive_fault is not None and self._link_up and not self._estop
                and self.fault_reset.may_try(self._time()))

    def reset_faults(self) -> list[str]:
        """Re-enable the motors after a drive fault (P2OS: ENABLE 1, as the motor button does),
        zero first. An explicit act, never automatic; refused (FaultResetError) while motion
        is commanded, while the e-stop is pressed, or without the option `reset_faults`. The
        fault clears when a SIP shows the motors on; the command stays zero until the next
        `command()`. Returns the devices a reset was sent for (none when there was no fault)."""
        now = self._time()
        where = f"{self.url}: P2OS motors"
        self.fault_reset.refuse_unless_allowed(now, where)
        if self.drive_fault is None:
            return []
        if self._estop:
            raise FaultResetError(f"{where}: fault reset refused: the e-stop is still pressed "
                                  f"(SIP FLAGS bit 5); release it first")
        with self._lock:
            if not self._link_up:
                raise FaultResetError(f"{where}: fault reset refused: the link is down")
            self._cmd = (0, 0)
            self.watchdog.disarm()
            self._send_velocity(0, 0, now)
            device, meaning = self.drive_fault["device"], self.drive_fault["meaning"]
            self._motors_seen = False
            self.fault_reset.start(now)         # before ENABLE: its SIP may come at once
            port = self._port
            try:
                port.write(p.enable(True))
            except (serial.SerialException, OSError, AttributeError) as exc:
                self.fault_reset.refuse(now, f"ENABLE could not be sent ({exc})")
                self._link_lost(f"write failed: {exc}")
                raise FaultResetError(f"{where}: fault reset: ENABLE could not be sent ({exc})") from exc
        log.warning("%s: drive fault reset: ENABLE 1 sent (%s)", self.url, meaning)
        return [device]

    def _fault_extra(self) -> dict:
        fault = self.drive_fault
        if fault is None:
            return {}
        return {"fault_resettable": self.fault_resettable(),"fault": f"{fault['device']}: {fault['meaning']}", "fault_device": fault["device"],
                "fault_code": fault["code"], "fault_meaning": fault["meaning"]}

    def _ring_size(self, factors: p.Factors) -> int:
        """How many sonars readings may name: the profile's ring, else the controller's."""
        return self.sonar_count if self.sonar_count is not None else factors.sonars

    def _drop(self, why: str) -> None:
        """A reading the profile does not describe: count it, keep the newest reason."""
        self.stats["dropped_readings"] += 1
        if why != self.dropped_reason:
            log.debug("%s: dropped a reading: %s", self.url, why)
        self.dropped_reason = why

    def wait_for_sip(self, after: int, timeout: float) -> bool:
        """Block until more than `after` SIPs were decoded (benchmarks and tests)."""
        with self._state_cond:
            return self._state_cond.wait_for(lambda: self.stats["sips"] > after, timeout)

    # -- liveness and reconnecting ------------------------------------------------------------------
    def _check_liveness(self, now: float) -> None:
        if self._link_up and now - self._last_sip_t > (MISSED_CYCLES + 0.5) * SIP_CYCLE:
            self._link_lost(f"no SIP for {now - self._last_sip_t:.2f} s "
                            f"({MISSED_CYCLES} cycles missed)")

    def _link_lost(self, why: str) -> None:
        with self._lock:
            if not self._link_up:
                return
            self.last_error = f"{self.url}: link down: {why}"
            log.warning("%s", self.last_error)
            self.stats["link_downs"] += 1
            self._stop_on_the_way_out()
            self._drop_port()
            self._set_link(False, why)
            self._cmd = (0, 0)
            self.watchdog.disarm()
            self._next_attempt = self._time() + self.backoff.next_delay()

    def _reconnect_with_backoff(self) -> None:
        delay = max(0.0, self._next_attempt - self._time())
        if self._closing.wait(delay):
            return
        try:
            self._connect()
        except LinkError as exc:
            self.last_error = str(exc)
            self._next_attempt = self._time() + self.backoff.next_delay()
            return
        self.backoff.reset()
        self.stats["reconnects"] += 1

    def _try_reconnect(self, now: float) -> None:
        if self.reconnect and now >= self._next_attempt:
            self._reconnect_with_backoff()

    def _stop_on_the_way_out(self) -> None:
        """Zero before dropping a port that may still carry it (a silent or garbled robot).

        The controller would otherwise keep the last command until its own 2 s watchdog, and
        resume it on the next packet (p2os.md §8)."""
        port = self._port
        if port is None:
            return
        try:
            port.write(p.vel(0) + p.rvel(0))
        except Exception:
            pass                               # the line is gone: nothing to stop through

    def _drop_port(self) -> None:
        port, self._port = self._port, None
        if port is not None:
            port.close()

    def _set_link(self, up: bool, why: str = "") -> None:
        self._link_up = up
        with self._state_cond:
            if self._state.link_up != up:
                extra = dict(self._state.extra)
                if not up:
                    extra["link_error"] = why or "link closed"
                    extra["link_device"] = self.link_device
                self._state = replace(self._state, link_up=up, t=self._now(),
                                      v=self._state.v if up else 0.0,
                                      w=self._state.w if up else 0.0, extra=extra)
            self._state_cond.notify_all()

    # -- sending ----------------------------------------------------------------------------------
    def _send_velocity(self, mm: int, deg: int, now: float) -> None:
        """VEL and RVEL in one write (caller holds the lock)."""
        port = self._port
        if port is None:
            return
        try:
            port.write(p.vel(mm) + p.rvel(deg))
        except (serial.SerialException, OSError) as exc:
            self._link_lost(f"write failed: {exc}")
            return
        self._sent, self._sent_at = (mm, deg), now

    def _on_stale(self) -> None:
        """Watchdog: no fresh command for WATCHDOG s -> zero, once."""
        with self._lock:
            if self.watchdog.armed:          # a command came in while we were waking up
                return
            self._cmd = (0, 0)
            self.stats["watchdog_stops"] += 1
            if self._link_up:
                self._send_velocity(0, 0, self._time())

    @property
    def link_up(self) -> bool:
        return self._link_up


def _sonar_count(profile) -> int | None:
    """The number of sonars the profile describes (None when it describes no ring)."""
    return len(profile.sonar.poses) if profile.sonar is not None else None


def _toward_zero_within(value: float, limit: float) -> int:
    """Round to the protocol's integer unit without exceeding `limit` in magnitude."""
    n = round(value)
    bound = math.floor(limit + 1e-9)
    return max(-bound, min(bound, n))
