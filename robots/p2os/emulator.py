"""A P2OS firmware emulator: the robot side of the wire, around a body in the simulated world.

It answers the handshake as the firmware does (echoes SYNC0/SYNC1, answers SYNC2 with name,
class and subclass), streams a SIP every 100 ms while open (sonar on from OPEN), drives the
world's body as the manuals describe the controller (velocity, heading and position servos,
the subclass's absolute limits under SETV/SETRV, SETA/SETRA ramps, STOP and ESTOP; CONFIG
answered with a CONFIGpac), stops the body after 2 s without any client packet and
re-accelerates to the last command on the next packet (the real firmware's watchdog, which the
driver must guard against), and reports sonar, bumpers and stall from the world. What each
command does, or why it is ignored: docs/emulator-fidelity.md.

Transports: a raw-mode pty (`serve_pty`) or a TCP port like MobileSim (`serve_tcp`). A reader
thread answers packets as they arrive, so the handshake works even while a simulated clock
stands still.

Two ways to keep time:
- Lock-step (`LockStep` given, a simulated clock): SIPs, snapshots and the firmware watchdog run
  in the world's step hook, in sim time. Every byte the driver wrote is processed (and the body
  command set) before the driver's write returns, and every SIP is written in the hook before
  the driver's `poll()` reads it, so a `--fast` run is deterministic.
- Real time (no lock-step): `start_clock()` runs a thread that emits SIPs every 100 ms of the
  clock and checks the watchdog; the world is either stepped by its own tick loop (whose hook
  only refreshes the snapshot the thread encodes), or, standing alone, by this thread
  (`start_clock(simulation)`).
"""
from __future__ import annotations

import math
import termios
import time
from collections import deque
from dataclasses import dataclass, replace

import numpy as np

from robots.exceptions import LinkError
from robots.link.host import EmulatorHost
from robots.link.lockstep import LockStep
from robots.link.pty import PtyPair
from robots.p2os import protocol as p

SIP_CYCLE = 0.1               # s
FIRMWARE_WATCHDOG = 2.0       # s without any client packet
BATTERY_DECIVOLTS = 125
ESTOP_FLAG = 0x20             # SIP FLAGS bit 5: e-stop (ARIA, later firmware)
BUMPER_FRONT, BUMPER_REAR = 1, 2          # the world's bumper bits
ALL_BUMPER_SEGMENTS = 0x3E                # bits 1..5 of a bumper byte
# FLASH acceleration defaults are per robot (the owner sets them), so `for_profile` takes the
# profile's; these are only the fallback. The tops cap SETA/SETRA (assumed: not in the notes).
DEFAULT_TRANS_ACCEL, DEFAULT_ROT_ACCEL = 300, 100   # mm/s^2, deg/s^2
TRANS_ACCEL_TOP, ROT_ACCEL_TOP = 2000, 500          # mm/s^2, deg/s^2
ARRIVED_MM, ARRIVED_DEG = 2.0, 0.5                  # MOVE and HEAD count as done within these
SERVO_GAIN = 3.0                                    # 1/s: the position servos' final approach
BAUD_CONSTANTS = {9600: termios.B9600, 19200: termios.B19200, 38400: termios.B38400,
                  57600: termios.B57600, 115200: termios.B115200}


def _odometry(world):
    """What the encoders count: the world's wheel odometry (drifting from the body's true pose),
    or the body itself in a bare stand-in world without one."""
    return getattr(world, "odometry", world.body)


@dataclass(frozen=True)
class Snapshot:
    """What the firmware reports, sampled from the world on the thread that steps it."""
    x: float = 0.0
    y: float = 0.0
    th: float = 0.0
    v: float = 0.0
    w: float = 0.0
    sonar: tuple[float, ...] = ()
    bumpers: int = 0
    stalled: bool = False

    @classmethod
    def of(cls, world) -> "Snapshot":
        odometry = _odometry(world)
        return cls(odometry.x, odometry.y, odometry.th, odometry.v, odometry.w,
                   tuple(np.asarray(world.sonar_ranges(), dtype=float).tolist()),
                   int(world.bumpers), bool(world.stalled))


class Firmware:
    """The controller's state machine, pure: packets in, reply bytes and a drive command out.

    Motion is two servos, as on the controller: translation follows a velocity (VEL, VEL2) or
    a relative distance (MOVE); rotation a velocity (RVEL, ROTATE, VEL2) or a heading (HEAD,
    DHEAD), which the SIP's CONTROL field reports. Targets are capped by SETV/SETRV, which are
    themselves capped by the subclass's absolute limits (p2os.md §7); the body ramps towards
    them at SETA/SETRA's acceleration (speeding up) or deceleration (slowing down). STOP
    decelerates, ESTOP stops at once (`estop_pending` tells the host to zero the body).
    """

    def __init__(self, factors: p.Factors, name: str = "horos", klass: str = "Pioneer",
                 sonar_max_range: float = 5.0, trans_accel: float = DEFAULT_TRANS_ACCEL,
                 rot_accel: float = DEFAULT_ROT_ACCEL) -> None:
        self.factors = factors
        self.name, self.klass = name, klass
        self.sonar_max_units = math.ceil(sonar_max_range * 1000.0 / factors.range)
        self.flash = {"trans_accel": int(trans_accel), "trans_decel": int(trans_accel),
                      "rot_accel": int(rot_accel), "rot_decel": int(rot_accel)}
        self.power_up()

    def power_up(self) -> None:
        """The FLASH values (SETV/SETRV/SETA/SETRA persist across CLOSE until power-up)."""
        self.origin = (0.0, 0.0, 0.0)
        self.max_vel = self.factors.max_vel
        self.max_rvel = self.factors.max_rvel
        self.estop = False           # the e-stop button held (tests): motors off, ENABLE ignored
        self.trans_accel = self.flash["trans_accel"]
        self.trans_decel = self.flash["trans_decel"]
        self.rot_accel = self.flash["rot_accel"]
        self.rot_decel = self.flash["rot_decel"]
        self.reset()

    def reset(self) -> None:
        """CLOSE / hang-up: not connected, motors off, no command."""
        self.sync_stage = 0          # next SYNC expected (0, 1, 2), 3 = synced
        self.open = False
        self.motors = False
        self.sonar_on = False
        self.vel = 0                 # mm/s commanded (translation in velocity mode)
        self.rvel = 0                # deg/s commanded (rotation in velocity mode)
        self.move_goal: tuple[float, float, float, float] | None = None  # x0, y0, th0, mm
        self.heading: float | None = None   # rad, world frame, while the heading servo rules
        self.estop_pending = False
        self.last_packet_t: float | None = None
        self.watchdog_tripped = False
        self.packets = 0
        self.ignored = 0

    # -- client packets ---------------------------------------------------------------------
    def receive(self, packet: p.Packet, now: float, pose: tuple[float, float, float]) -> bytes:
        """Act on one checked client packet; return what the firmware sends back (maybe nothing)."""
        self.packets += 1
        self.last_packet_t = now
        self.watchdog_tripped = False          # the drives resume on any packet
        if not self.open:
            return self._handshake(packet)
        try:
            arg = p.decode_argument(packet.data)
        except Exception:
            self.ignored += 1
            return b""
        return self._command(packet.kind, arg, pose)

    def _handshake(self, packet: p.Packet) -> bytes:
        kind = packet.kind
        if kind == p.Cmd.SYNC0:
            self.sync_stage = 1
            return p.sync_echo(0)
        if kind == p.Cmd.SYNC1 and self.sync_stage == 1:
            self.sync_stage = 2
            return p.sync_echo(1)
        if kind == p.Cmd.SYNC2 and self.sync_stage == 2:
            self.sync_stage = 3
            return p.sync2_reply(self.name, self.klass, self.factors.subclass)
        if kind == p.Cmd.OPEN and self.sync_stage == 3:
            self.open = True
            self.sonar_on = True               # the manuals: sonar fires from OPEN on
            return b""
        self.sync_stage = 0
        self.ignored += 1
        return b""

    def _command(self, kind: int, arg, pose) -> bytes:
        as_int = arg if isinstance(arg, int) else 0
        if kind == p.Cmd.CLOSE:
            self.reset()
        elif kind == p.Cmd.ENABLE:
            self.motors = bool(as_int) and not self.estop
        elif kind == p.Cmd.VEL:
            self.vel, self.move_goal = as_int, None
        elif kind in (p.Cmd.RVEL, p.Cmd.ROTATE):
            self.rvel, self.heading = as_int, None
        elif kind == p.Cmd.VEL2:
            left, right = p.vel2_wheels(as_int)
            div = self.factors.vel2_divisor
            self.vel = round((left + right) * div / 2)
            self.rvel = round(math.degrees((right - left) * div / 2 * self.factors.diff))
            self.move_goal = self.heading = None
        elif kind == p.Cmd.HEAD:
            self.heading = self.origin[2] + math.radians(as_int)
        elif kind == p.Cmd.DHEAD:
            self.heading = pose[2] + math.radians(as_int)
        elif kind == p.Cmd.MOVE:
            self.move_goal = (pose[0], pose[1], pose[2], float(as_int))
        elif kind in (p.Cmd.STOP, p.Cmd.ESTOP):
            self.vel = self.rvel = 0
            self.move_goal = self.heading = None
            self.estop_pending = kind == p.Cmd.ESTOP
        elif kind == p.Cmd.SETV:
            self.max_vel = min(abs(as_int), self.factors.max_vel)
        elif kind == p.Cmd.SETRV:
            self.max_rvel = min(abs(as_int), self.factors.max_rvel)
        elif kind == p.Cmd.SETA and as_int:          # 0 would never start or never stop: ignored
            self._set_accel("trans", as_int, TRANS_ACCEL_TOP)
        elif kind == p.Cmd.SETRA and as_int:
            self._set_accel("rot", as_int, ROT_ACCEL_TOP)
        elif kind == p.Cmd.SONAR:
            if as_int & 1 or not as_int >> 1:
                self.sonar_on = bool(as_int & 1)
            else:                               # one array off: arrays are not modelled, and
                self.ignored += 1               # switching them all off would be unsafe
        elif kind == p.Cmd.SETO:
            self.origin = pose
        elif kind == p.Cmd.CONFIG:
            return self.config_packet()
        elif kind == p.Cmd.PULSE:
            pass
        else:                                   # BUMPSTALL, SAY, ENCODER, ...: see the docs
            self.ignored += 1
        return b""

    def _set_accel(self, axis: str, value: int, top: int) -> None:
        """SETA/SETRA: a positive value sets the acceleration, a negative one the deceleration."""
        which = "accel" if value > 0 else "decel"
        setattr(self, f"{axis}_{which}", min(abs(value), top))

    def config_packet(self) -> bytes:
        """The CONFIGpac: the subclass's tops and the current settings."""
        f = self.factors
        return p.encode_config({
            "robot_type": self.klass, "subtype": f.subclass, "serial": "emulated",
            "rot_vel_top": f.max_rvel, "trans_vel_top": f.max_vel,
            "rot_accel_top": ROT_ACCEL_TOP, "trans_accel_top": TRANS_ACCEL_TOP,
            "pwm_max": 1000, "name": self.name, "sip_cycle_ms": round(SIP_CYCLE * 1000),
            "front_sonar": 1 if f.sonars else 0, "rear_sonar": 1 if f.sonars > 16 else 0,
            "low_battery": 110, "watchdog_ms": round(FIRMWARE_WATCHDOG * 1000),
            "rot_vel_max": self.max_rvel, "trans_vel_max": self.max_vel,
            "rot_accel": self.rot_accel, "rot_decel": self.rot_decel,
            "trans_accel": self.trans_accel, "trans_decel": self.trans_decel,
            "front_bumps": 5, "rear_bumps": 5, "sonar_cycle_ms": 40,
            "firmware_version": "interbot P2OS emulator"})

    # -- time ----------------------------------------------------------------------------------
    def press_estop(self, held: bool = True) -> None:
        """The e-stop button (tests): pressed, the motors go off at once and ENABLE is ignored
        while held (SIP FLAGS bit 5); released, the motors stay off until ENABLE 1."""
        self.estop = held
        if held:
            self.motors = False
            self.vel = self.rvel = 0
            self.move_goal = self.heading = None
            self.estop_pending = True

    def switch_motors_off(self) -> None:
        """The MOTORS button pressed while on (tests): motors off until ENABLE 1."""
        self.motors = False
        self.vel = self.rvel = 0

    def check_watchdog(self, now: float) -> bool:
        """Trip after FIRMWARE_WATCHDOG s without a packet; True when it just tripped."""
        if (self.open and not self.watchdog_tripped and self.last_packet_t is not None
                and now - self.last_packet_t >= FIRMWARE_WATCHDOG):
            self.watchdog_tripped = True
            return True
        return False

    def drive(self, pose: tuple[float, float, float] | None = None) -> tuple[float, float]:
        """The (v m/s, w rad/s) the servos aim for now, at this (world-frame) pose."""
        if not (self.open and self.motors) or self.watchdog_tripped:
            return 0.0, 0.0
        vel = max(-self.max_vel, min(self.max_vel, self.vel))
        rvel = max(-self.max_rvel, min(self.max_rvel, self.rvel))
        if pose is not None and self.move_goal is not None:
            vel = self._move_speed(pose)
        if pose is not None and self.heading is not None:
            rvel = self._heading_speed(pose)
        return vel / 1000.0, math.radians(rvel)

    def _move_speed(self, pose) -> float:
        """MOVE's position servo: mm/s towards the goal, slowing to arrive at the deceleration."""
        x0, y0, th0, goal = self.move_goal
        done = (pose[0] - x0) * math.cos(th0) + (pose[1] - y0) * math.sin(th0)
        left = goal - done * 1000.0
        if abs(left) <= ARRIVED_MM:
            return 0.0
        speed = min(self.max_vel, math.sqrt(2 * self.trans_decel * abs(left)),
                    SERVO_GAIN * abs(left))
        return math.copysign(speed, left)

    def _heading_speed(self, pose) -> float:
        """The heading servo: deg/s towards the setpoint, slowing to arrive at the deceleration."""
        error = math.degrees(p.normalize_angle(self.heading - pose[2]))
        if abs(error) <= ARRIVED_DEG:
            return 0.0
        speed = min(self.max_rvel, math.sqrt(2 * self.rot_decel * abs(error)),
                    SERVO_GAIN * abs(error))
        return math.copysign(speed, error)

    def ramp(self, current: tuple[float, float], target: tuple[float, float]) -> tuple[float, float]:
        """(m/s², rad/s²) to ramp at: acceleration when speeding up, deceleration otherwise."""
        def rate(now: float, want: float, accel: float, decel: float) -> float:
            speeding_up = abs(want) > abs(now) and (now == 0 or (want > 0) == (now > 0))
            return accel if speeding_up else decel
        return (rate(current[0], target[0], self.trans_accel, self.trans_decel) / 1000.0,
                math.radians(rate(current[1], target[1], self.rot_accel, self.rot_decel)))

    # -- status --------------------------------------------------------------------------------
    def sip(self, snap: Snapshot) -> bytes:
        """The SIP for this world snapshot, in the odometry frame set by SETO."""
        f = self.factors
        ox, oy, oth = self.origin
        c, s = math.cos(oth), math.sin(oth)
        dx, dy = snap.x - ox, snap.y - oy
        x_mm, y_mm = (c * dx + s * dy) * 1000.0, (-s * dx + c * dy) * 1000.0
        th = p.normalize_angle(snap.th - oth)
        control = p.normalize_angle((self.heading if self.heading is not None else snap.th) - oth)
        half = snap.w / f.diff               # mm/s of (R - L) / 2
        left = _i16(snap.v * 1000.0 - half)
        right = _i16(snap.v * 1000.0 + half)
        stall_bumpers = 0
        if snap.bumpers & BUMPER_FRONT:
            stall_bumpers |= ALL_BUMPER_SEGMENTS << 8
        if snap.bumpers & BUMPER_REAR:
            stall_bumpers |= ALL_BUMPER_SEGMENTS
        if snap.stalled:
            stall_bumpers |= 0x0101
        flags = ((0x01 if self.motors else 0) | (0x02 if self.sonar_on else 0)
                 | (ESTOP_FLAG if self.estop else 0))
        sonar = self._sonar_units(snap.sonar) if self.sonar_on else ()
        return p.encode_sip(p.SIP(
            moving=bool(snap.v or snap.w), xpos=round(x_mm / f.dist) & 0x7FFF,
            ypos=round(y_mm / f.dist) & 0x7FFF, thpos=_i16(th / f.angle), lvel=left, rvel=right,
            battery=BATTERY_DECIVOLTS, stall_bumpers=stall_bumpers,
            control=_i16(control / f.angle), flags=flags, sonar=sonar))

    def _sonar_units(self, ranges: tuple[float, ...]) -> tuple[tuple[int, int], ...]:
        """(number, units) of every reading: the nearest unit, at least 0, at most the
        sonar's maximum, which no echo (inf, NaN) reports too. One pass for 16-48 sonars a SIP."""
        top, unit, isfinite = self.sonar_max_units, self.factors.range, math.isfinite
        return tuple((i, min(top, max(0, round(r * 1000.0 / unit))) if isfinite(r) else top)
                     for i, r in enumerate(ranges))


def _i16(value: float) -> int:
    return max(-32768, min(32767, round(value)))


class P2OSEmulator(EmulatorHost):
    """The firmware on a transport, around `world.body`. See the module docstring for timing."""

    name = "p2os-emulator"
    read_timeout = 0.1

    def __init__(self, world, subclass: str = "p2dx", name: str = "horos",
                 sonar_max_range: float = 5.0, clock=None, lockstep: LockStep | None = None,
                 baud: int | None = None, trans_accel: float = DEFAULT_TRANS_ACCEL,
                 rot_accel: float = DEFAULT_ROT_ACCEL) -> None:
        factors = p.factors_for(subclass)
        if factors is None:
            raise LinkError(f"P2OS emulator: unknown subclass {subclass!r}; known: "
                            f"{', '.join(sorted(p.FACTORS))}")
        if baud is not None and baud not in BAUD_CONSTANTS:
            raise LinkError(f"P2OS emulator: baud {baud} not one of {sorted(BAUD_CONSTANTS)}")
        super().__init__(lockstep)
        self.world = world
        self.firmware = Firmware(factors, name, sonar_max_range=sonar_max_range,
                                 trans_accel=trans_accel, rot_accel=rot_accel)
        # The body obeys the controller's absolute limits, not our profile's safe ones (those
        # are the driver's business); the firmware sets its acceleration as it ramps.
        self._body_limits = replace(world.body.limits, max_speed=factors.max_vel / 1000.0,
                                    max_turn_rate=math.radians(factors.max_rvel))
        world.body.limits = self._body_limits
        self._ramp: tuple[float, float] | None = None    # `_apply`'s last rates and their Limits
        self._ramped = self._body_limits
        self.clock = clock
        self.baud = baud
        self.sips_sent = 0
        self.received: deque[tuple[float, p.Packet]] = deque(maxlen=10_000)  # (monotonic, packet)
        self.parser = p.P2OSParser()
        self._snapshot = Snapshot.of(world)
        self._next_sip: float | None = None
        self._snapshot_due = 0.0
        self._hooked = False

    @classmethod
    def for_profile(cls, profile, world, **kw) -> "P2OSEmulator":
        """An emulator shaped like `profile`'s base (subclass, name, sonar range); the FLASH
        accelerations are this robot's physical ones (the profile's), set by its owner."""
        max_range = profile.sonar.max_range if profile.sonar is not None else 5.0
        limits = profile.limits
        kw.setdefault("trans_accel", round(limits.max_accel * 1000.0))
        kw.setdefault("rot_accel", round(math.degrees(limits.max_turn_accel)))
        return cls(world, subclass=profile.base.options.get("subclass", "p2dx"),
                   name=profile.name, sonar_max_range=max_range, **kw)

    def press_estop(self, held: bool = True) -> None:
        """The e-stop button, pressed or released (tests; `Firmware.press_estop`)."""
        with self._lock:
            self.firmware.press_estop(held)
            self._apply()

    def switch_motors_off(self) -> None:
        """The MOTORS button pressed while the motors are on (tests)."""
        with self._lock:
            self.firmware.switch_motors_off()
            self._apply()

    # -- time ----------------------------------------------------------------------------------
    def now(self) -> float:
        if self.lockstep is not None or self.clock is None:
            return float(self.world.t)
        return self.clock.now()

    def attach(self, simulation) -> None:
        """Hook into the simulation's steps (lock-step SIPs, or snapshots for the clock thread)."""
        if not self._hooked:
            simulation.on_step(self._on_world_step)
            self._hooked = True

    def _on_world_step(self, world, dt: float) -> None:
        with self._lock:
            self._apply()                        # MOVE and HEAD servo on the new pose
        if self.lockstep is not None:
            self.tick(world.t)
        elif world.t >= self._snapshot_due:      # real time: the clock thread encodes it
            self._snapshot = Snapshot.of(world)
            self._snapshot_due = world.t + SIP_CYCLE / 2

    def tick(self, now: float) -> None:
        """The firmware's cycle: watchdog, then a SIP when one is due."""
        with self._lock:
            if self.firmware.check_watchdog(now):
                self._apply()
            if not self.firmware.open:
                self._next_sip = None
                return
            if self._next_sip is None:           # first SIP: on the cycle grid in lock-step
                self._next_sip = (math.ceil(now / SIP_CYCLE - 1e-6) * SIP_CYCLE
                                  if self.lockstep is not None else now)
            if now + 1e-9 < self._next_sip:
                return
            self._next_sip = max(self._next_sip + SIP_CYCLE, now + SIP_CYCLE / 2)
            if self.lockstep is not None:
                self._snapshot = Snapshot.of(self.world)
                snapshot = self._snapshot
            else:
                snapshot = self._sampled_now(now)
            self._send(self.firmware.sip(snapshot))
            self.sips_sent += 1

    def _sampled_now(self, now: float) -> Snapshot:
        """Real time: the odometry pose at SIP time (moved on from the world's last step at its
        velocities), with the newest sonar sweep; not a copy up to half a cycle old."""
        odometry = _odometry(self.world)
        x, y, th, v, w = odometry.x, odometry.y, odometry.th, odometry.v, odometry.w
        ahead = min(max(0.0, now - float(self.world.t)), SIP_CYCLE)
        if ahead > 0:
            if abs(w) < 1e-9:
                x, y = x + v * ahead * math.cos(th), y + v * ahead * math.sin(th)
            else:
                th2 = th + w * ahead
                x += v / w * (math.sin(th2) - math.sin(th))
                y -= v / w * (math.cos(th2) - math.cos(th))
                th = th2
        return replace(self._snapshot, x=x, y=y, th=p.normalize_angle(th), v=v, w=w)

    def start_clock(self, simulation=None, period: float = 0.01) -> None:
        """Real-time mode: a thread runs `tick` every `period` s (and steps `simulation` if given)."""
        def run() -> None:
            while not self._stop.wait(period):
                now = self.clock.now()
                if simulation is not None:
                    simulation.advance(now)
                self.tick(now)
        self._spawn(run, "p2os-emulator-clock")

    # -- hosting hooks (robots.link.host) -----------------------------------------------------
    def on_connect(self) -> None:
        self.parser.reset()

    def on_hangup(self) -> None:
        """A client that left leaves the robot closed and stopped, as the firmware would."""
        self.firmware.reset()
        self._apply()

    def line_ok(self, pty: PtyPair) -> bool:
        return self.baud is None or pty.line_speed() == BAUD_CONSTANTS[self.baud]

    def receive(self, data: bytes) -> None:
        """Bytes from the client: act on every whole packet, answer, then count them as read."""
        with self._lock:
            now = self.now()
            odometry = _odometry(self.world)     # the firmware knows only its encoders
            pose = (odometry.x, odometry.y, odometry.th)   # MOVE, DHEAD and SETO start here
            arrived = time.monotonic()
            for packet in self.parser.feed(data):
                self.received.append((arrived, packet))
                was_open = self.firmware.open
                reply = self.firmware.receive(packet, now, pose)
                if reply:
                    self._send(reply)
                self._apply()
                if was_open and not self.firmware.open:
                    self.end_session()           # CLOSE ends a TCP session
        if self.lockstep is not None:
            self.lockstep.to_device.got(len(data))

    def _apply(self) -> None:
        """Hand the servos' targets to the body, ramped at the firmware's rates."""
        body, firmware = self.world.body, self.firmware
        odometry = _odometry(self.world)
        target = firmware.drive((odometry.x, odometry.y, odometry.th))
        if firmware.estop_pending:               # ESTOP overrides the deceleration
            firmware.estop_pending = False
            body.v = body.w = 0.0
        ramp = firmware.ramp((body.v, body.w), target)
        if ramp != self._ramp:                   # a new Limits only when the rates change
            self._ramp = ramp
            self._ramped = replace(self._body_limits, max_accel=ramp[0], max_turn_accel=ramp[1])
        body.limits = self._ramped
        body.set_command(*target)

