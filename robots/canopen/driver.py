"""The CAN base driver: a differential drive with two CiA 402 drives, through python-can.

`CanOpenBase(limits, port)` opens any python-can interface (`socketcan:can0`,
`pcan:PCAN_USBBUS1`, `virtual:NAME`, `socketcand:127.0.0.1:PORT`; see `robots.canopen.bus`).
`open()` runs the start-up of ../shared/protocols/canopen-drive.md §2: NMT reset communication
and the boot-ups, SDO configuration in pre-operational (profile velocity mode, ramps, maximum
velocity, quick-stop reaction, PDO mapping, heartbeats), NMT start, then the CiA 402 state
machine to Operation Enabled with the statusword read back after each step. From then on:
SYNC every `sync_period`, each drive answers with TPDO1 (statusword, velocity) and TPDO2
(position), odometry integrates the two wheels, and RPDO1 carries controlword and target.

`canopen` does the SDO client (expedited transfers, abort codes, time-outs), the object
dictionary and NMT commands; we do heartbeat supervision (it has no time-out alarm), the PDOs
(our fixed layout, packed by `protocol`), SYNC, EMCY handling and the 402 sequence.

Safety:
- The host watchdog (`robots.link.CommandWatchdog`) sends zero velocity 0.15 s after the last
  `command()`; the next `command()` moves again, as with the serial bases.
- Faults: an EMCY, a statusword with the fault bit (or leaving Operation Enabled), a drive's
  heartbeat older than its time-out or a boot-up in operation, the bus going error-passive or
  bus-off, a failed send. Each stops both wheels (quick stop, target 0), sets `link_up` False
  and names the cause in `BaseState.extra["fault"]`; the safety arbiter then holds still.
  Nothing moves again until `activate()` is called; a drive in Fault is reset only by
  `reset_faults()`. The host's heartbeat (node 0x7F) lets the drives quick-stop by themselves
  when the host dies (0x1016, 0x6007 = 3).

On a simulated clock (`for_simulation`) no driver thread runs: `poll()` sends the heartbeat and
the SYNC in sim time and waits (frames counted by `LockStep`) until every frame the emulator
sent has been handled, so a `--fast` run is deterministic. In real time a cycle thread sends
SYNC and the heartbeat, the RPDOs follow each cycle's TPDOs, and the watchdog has its thread.
"""
from __future__ import annotations

import logging
import math
import os
import struct
import threading
import time
from dataclasses import replace

import can
import canopen
from canopen.sdo import SdoAbortedError, SdoCommunicationError

from robots.base import Base, BaseState, clamp_velocity
from robots.canopen import protocol as p
from robots.canopen.objects import ABSENT_CODES, OPTIONAL, described
from robots.canopen.bus import CandumpLog, Counted, DriverBus, open_bus, parse_port
from robots.canopen.od import drive_dictionary
from robots.canopen.wheels import DriveConfig, Odometry, wrap_delta
from robots.exceptions import HandshakeError
from robots.link.lockstep import LockStep
from robots.link.watchdog import CommandWatchdog
from robots.profile import Limits

log = logging.getLogger(__name__)
S = p.State402
WATCHDOG = 0.15             # s without a fresh command -> zero
BUS_STATE_EVERY = 0.5       # s between polls of the interface's error state (real time)
LOG_ENV = "INTERBOT_CAN_LOG"
NOTIFIER_CYCLE = 0.05       # s, longest the receive thread blocks (canopen's default is 1 s)
SELF_CHECK_SPEED = 0.05     # m/s at the wheel during the start-up self-check
PLAUSIBLE = (0.5, 2.0)      # self-check: measured / expected outside this is a contradiction


class StartupError(HandshakeError):
    """A drive did not come up as CiA 301/402 say; the message names node, object and cause."""


class CanOpenBase(Base):
    """Two CiA 402 wheel drives on a CAN bus. Options: the `DriveConfig` fields, `can_log`
    (candump -l file), `reset_faults` (clear drive faults in `open`), `lockstep`."""

    def __init__(self, limits: Limits, port: str, clock=None, config: DriveConfig | None = None,
                 **options) -> None:
        super().__init__(limits)
        self.port = port
        self.spec = parse_port(port)
        self.clock = clock
        self.simulated = bool(getattr(clock, "simulated", False))
        self.lockstep: LockStep | None = options.pop("lockstep", None)
        self.can_log_path = options.pop("can_log", None) or self.spec.log or os.environ.get(LOG_ENV)
        self.reset_faults_on_open = bool(options.pop("reset_faults", False))
        initial_pose = options.pop("initial_pose", (0.0, 0.0, 0.0))
        self.config = config or DriveConfig.from_options(options, "CanOpenBase options")
        c = self.config
        self.nodes = (c.left_node, c.right_node)
        self.watchdog = CommandWatchdog(float(options.pop("watchdog", WATCHDOG)), self._on_stale,
                                        name="canopen-watchdog", time_source=self._time)
        self.emulator = None
        self.network: canopen.Network | None = None
        self.remote: dict[int, canopen.RemoteNode] = {}
        self.can_log: CandumpLog | None = None
        self.odometry = Odometry(c)
        self.odometry.x, self.odometry.y, self.odometry.th = (float(v) for v in initial_pose)
        self.stats = {"syncs": 0, "tpdos": 0, "rpdos": 0, "emcys": 0, "watchdog_stops": 0,
                      "faults": 0, "cycles": 0}
        self.fault_log: list[dict] = []         # each fault: reason, t_event, t_zero (monotonic)
        self.emcy_log: list[tuple[int, p.Emcy]] = []
        self.rpdo_times: list[tuple[float, int, int]] = []   # (monotonic, node, target) for benchmarks
        self._lock = threading.RLock()
        self._state_cond = threading.Condition()
        self._state = BaseState(t=self._now(), x=self.odometry.x, y=self.odometry.y,
                                th=self.odometry.th, link_up=False)
        self._cmd = (0, 0)                      # target velocities (left, right), increments/s
        self._enabled = False                   # both drives in Operation Enabled, ours to drive
        self._fault: str | None = None
        self._fault_info: dict = {}             # the first fault: device, code, meaning
        self._requested = (0.0, 0.0, -math.inf)  # the last command() asked: v, w, when
        self._pending_faults: list[tuple[str, float]] = []
        self._boot_seen: dict[int, float] = {}
        self._boot_cond = threading.Condition()
        self._heartbeat_t: dict[int, float] = {}
        self._sw = {n: 0 for n in self.nodes}
        self._vel = {n: 0 for n in self.nodes}
        self._pos = {n: 0 for n in self.nodes}
        self._pos_seen = {n: 0 for n in self.nodes}
        self._vel_seen = {n: 0 for n in self.nodes}     # TPDO1s received per drive
        self._cycle_done = 0
        self._streaming = False                 # SYNC and RPDOs go out (driving, or stopping)
        self._powered = False                   # a drive was enabled by us (start-up got that far)
        self._controlword = p.Cw.ENABLE_OPERATION   # what RPDO1 carries: enable, or quick stop
        self._world_step = None                 # simulation: steps the world to a time (for_simulation)
        self.present: dict[int, dict[tuple[int, int], bool]] = {}   # optional objects found
        self.startup_notes: list[str] = []      # optional objects skipped, and why that is fine
        self.identity: dict[int, dict[str, int]] = {}
        self.self_check_result: dict[int, dict[str, float]] = {}
        self.stop_log: list[dict] = []          # each stop sequence: steps and times
        self._sonar: tuple[float, ...] = tuple([math.inf] * c.sonars)
        self._sonar_t = -math.inf               # when the sonar board last reported
        self.bus_state = "error-active"
        self._closing = threading.Event()
        self._cycle_thread: threading.Thread | None = None
        self._next_sync = 0.0
        self._next_heartbeat = 0.0
        self._next_bus_check = 0.0
        self.last_error = ""

    # -- wiring ----------------------------------------------------------------------------------
    PROFILE_OPTIONS = ("can_log", "reset_faults")       # besides the DriveConfig fields

    @classmethod
    def profile_problems(cls, options: dict) -> list[tuple[str, str]]:
        known = DriveConfig.field_names() | set(cls.PROFILE_OPTIONS)
        found = [(key, f"unknown canopen option {key!r}{_close(key, known)}; see docs/canopen.md")
                 for key in options if key not in known]
        if not isinstance(options.get("reset_faults", False), bool):
            found.append(("reset_faults", f"reset_faults = {options['reset_faults']!r} must be true or false"))
        return found + DriveConfig.problems(options)

    @classmethod
    def for_profile(cls, profile, port: str, clock=None) -> "CanOpenBase":
        """A driver for the real base on `port`, configured from the profile's [base] table."""
        options = dict(profile.base.options)
        config = DriveConfig.from_options(options, f"{profile.source} [base]")
        return cls(profile.limits, port, clock=clock, config=config,
                   can_log=options.get("can_log"), reset_faults=options.get("reset_faults", False))

    @classmethod
    def for_simulation(cls, profile, simulation, clock) -> "CanOpenBase":
        """The emulated drives on a virtual bus around `simulation.world`; a driver on that bus."""
        from robots.canopen.emulator import CanOpenEmulator     # emulator only when simulating
        lockstep = LockStep() if getattr(clock, "simulated", False) else None
        emulator = CanOpenEmulator.for_profile(profile, simulation.world, clock=clock, lockstep=lockstep)
        emulator.attach(simulation)
        if lockstep is None:
            emulator.start_clock()
        body = simulation.world.body
        base = cls(profile.limits, f"virtual:{emulator.channel}", clock=clock,
                   config=emulator.config, lockstep=lockstep,
                   reset_faults=profile.base.options.get("reset_faults", False),
                   can_log=profile.base.options.get("can_log"),
                   initial_pose=(body.x, body.y, body.th))
        base.emulator = emulator
        base._world_step = simulation.advance
        return base

    # -- time ----------------------------------------------------------------------------------
    def _now(self) -> float:
        return self.clock.now() if self.clock is not None else time.monotonic()

    def _time(self) -> float:
        """Watchdog and supervision time: sim time in lock-step, else monotonic."""
        return self.clock.now() if self.simulated else time.monotonic()

    def _who(self, node: int) -> str:
        return f"node {node} ({self.config.wheel_name(node)})"

    # -- Base interface ---------------------------------------------------------------------------
    def open(self) -> None:
        self._closing.clear()
        self._connect()
        try:
            if not self.simulated:
                self._cycle_thread = threading.Thread(target=self._cycle_loop, name="canopen-cycle",
                                                      daemon=True)
                self._cycle_thread.start()
            else:
                self._send_host_heartbeat()
            self._start_up()
        except Exception:
            self.close()
            raise
        if not self.simulated:
            self.watchdog.start()

    def read_state(self) -> BaseState:
        return self._state

    def command(self, v: float, w: float) -> None:
        v, w = clamp_velocity(v, w, self.limits)
        target = self.config.command_counts(v, w)
        with self._lock:
            self._requested = (v, w, self._time())
            self.watchdog.feed(self._time())
            if not self._enabled:
                return
            changed = target != self._cmd
            self._cmd = target
            if changed:
                self._send_targets()

    def stop(self) -> None:
        with self._lock:
            self._cmd = (0, 0)
            self.watchdog.disarm()
            if self._enabled:
                self._send_targets()

    def close(self) -> None:
        if self._closing.is_set() and self.network is None:
            return
        try:
            self._stop_drives("close")
        except Exception as exc:          # the heartbeat time-out remains the drives' backstop
            log.warning("%s: stopping the drives failed: %s", self.port, exc)
        self._closing.set()
        self.watchdog.stop()
        if self._cycle_thread is not None and self._cycle_thread is not threading.current_thread():
            self._cycle_thread.join(timeout=2.0)
        self._cycle_thread = None
        with self._lock:
            if self.network is not None:
                try:
                    self._send(*p.nmt(p.Nmt.PRE_OPERATIONAL))
                except Exception:
                    pass
                self._enabled = False
                self._streaming = False
                try:
                    self.network.disconnect()
                except Exception:
                    pass
                self.network = None
            self._set_link(False)
        if self.can_log is not None:
            self.can_log.close()
            self.can_log = None
        if self.emulator is not None:
            self.emulator.close()
            self.emulator = None

    def poll(self, timeout: float = 0.0) -> None:
        """Lock-step: heartbeat and SYNC in sim time, handle every frame, supervise."""
        if not self.simulated or self.network is None:
            return
        now = self._lockstep_cycle(timeout)
        self.watchdog.check(now)

    def _lockstep_cycle(self, timeout: float = 0.0) -> float:
        now = self._time()
        with self._lock:
            if now + 1e-9 >= self._next_heartbeat:
                self._send_host_heartbeat()
                self._next_heartbeat = now + self.config.host_heartbeat_ms / 1000.0
            if self._streaming and now + 1e-9 >= self._next_sync:
                self._send_sync()
                self._next_sync = now + self.config.sync_period
        self._drain(time.monotonic() + max(timeout, 2.0))
        self._supervise(now)
        with self._lock:
            if self._streaming:
                self._send_targets()
        return now

    # -- explicit recovery -------------------------------------------------------------------------
    def reset_faults(self) -> list[int]:
        """Clear a Fault on each drive with the fault-reset edge (an explicit act; never automatic).
        Returns the nodes that were in Fault. Motion stays off until `activate()`. Refused while
        motion is commanded (a non-zero command() within the watchdog time): a reset must never
        meet a command that would drive off with it."""
        v, w, when = self._requested
        if (v or w) and self._time() - when <= self.watchdog.timeout:
            raise StartupError(f"{self.port}: fault reset refused: motion is commanded (v {v:.2f} m/s, "
                               f"w {w:.2f} rad/s); command zero first")
        reset = []
        for node in self.nodes:
            sw = self._sdo_read(node, p.STATUSWORD, 0, "statusword")
            if p.state_of(sw) in (S.FAULT, S.FAULT_REACTION_ACTIVE):
                self._sdo_write(node, p.CONTROLWORD, 0, struct.pack("<H", 0), "controlword")
                self._sdo_write(node, p.CONTROLWORD, 0, struct.pack("<H", p.Cw.FAULT_RESET),
                                "controlword (fault reset)")
                self._expect_state(node, S.SWITCH_ON_DISABLED, "fault reset 0x0080")
                reset.append(node)
        return reset

    def activate(self) -> None:
        """After a fault: the whole start-up again (a rebooted drive lost its configuration).
        Refuses while a drive is in Fault; zero velocity until the next `command()`."""
        with self._lock:
            self._enabled = False
            self._cmd = (0, 0)
        self._start_up()

    # -- connection and start-up -----------------------------------------------------------------
    def _connect(self) -> None:
        bus = open_bus(self.spec, self.config.bitrate)
        if self.can_log_path:
            self.can_log = CandumpLog(self.can_log_path, self.spec.channel)
        if self.lockstep is not None:
            self.lockstep.reset()
        network = canopen.Network()
        network.NOTIFIER_CYCLE = NOTIFIER_CYCLE          # close() returns promptly
        network.bus = DriverBus(bus, self.lockstep.to_device if self.lockstep else None, self.can_log)
        network.listeners.append(_Raw(self))
        if self.lockstep is not None:
            network.listeners.append(Counted(self.lockstep.to_host))
        for node in self.nodes:
            remote = canopen.RemoteNode(node, drive_dictionary(node))
            remote.sdo.RESPONSE_TIMEOUT = self.config.sdo_timeout
            remote.sdo.MAX_RETRIES = 2
            network.add_node(remote)
            self.remote[node] = remote
            network.subscribe(p.heartbeat_id(node), self._on_heartbeat)
            network.subscribe(p.emcy_id(node), self._on_emcy)
            network.subscribe(p.tpdo_id(1, node), self._on_tpdo1)
            network.subscribe(p.tpdo_id(2, node), self._on_tpdo2)
        if self.config.sonar_node and self.config.sonars:
            for k in range(0, self.config.sonars, 4):
                network.subscribe(p.TPDO_BASE[k // 4] + self.config.sonar_node, self._on_sonar)
        network.connect()
        self.network = network

    def _start_up(self) -> None:
        """Reset, configure, start, enable: §2 of the protocol notes, checked at each step."""
        for node in self.nodes:          # a drive we drove before and that is now in Fault
            if node in self._heartbeat_t and self._state_of_node_quiet(node) in (
                    S.FAULT, S.FAULT_REACTION_ACTIVE):
                raise StartupError(f"{self._who(node)} is in Fault ({self._fault_text(node)}); "
                                   f"call reset_faults() first, after finding the cause")
        with self._lock:
            self._streaming = False
            self._controlword = p.Cw.ENABLE_OPERATION
        with self._boot_cond:
            self._boot_seen.clear()
        times = self.startup_timings = {"reset": time.monotonic()}
        self._send(*p.nmt(p.Nmt.RESET_COMMUNICATION))
        self._wait_boot()
        t0 = times["booted"] = time.monotonic()
        for node in self.nodes:
            self._configure(node)
        times["nmt_start"] = time.monotonic()
        self._send(*p.nmt(p.Nmt.START))
        self._powered = True
        for node in self.nodes:
            self._enable(node)
        times["enabled"] = time.monotonic()
        self._self_check()
        times["checked"] = time.monotonic()
        with self._lock:
            self.odometry.reset()
            self._cmd = (0, 0)
            self._fault = None
            self._fault_info = {}
            self._pending_faults.clear()
            now = self._time()
            for node in self.nodes:
                self._heartbeat_t[node] = now
            self._sonar_t = now
            self._enabled = True
            self._streaming = True
            self._send_targets()
            self._next_sync = now
            self._set_link(True)
        self.startup_time = time.monotonic() - t0
        log.info("%s: both drives in operation enabled (%.3f s after configuration began)",
                 self.port, self.startup_time)

    def _state_of_node_quiet(self, node: int):
        try:
            return p.state_of(self._sdo_read(node, p.STATUSWORD, 0, "statusword"))
        except StartupError:
            return None

    def _fault_text(self, node: int) -> str:
        try:
            code = self._sdo_read(node, p.ERROR_CODE, 0, "error code")
            return f"error {code:#06x}: {p.emcy_meaning(code)}"
        except StartupError:
            return "error code unreadable"

    def _wait_boot(self) -> None:
        deadline = time.monotonic() + self.config.boot_timeout
        with self._boot_cond:
            while not all(n in self._boot_seen for n in self.nodes):
                remaining = deadline - time.monotonic()
                if remaining <= 0 or self._closing.is_set():
                    break
                self._boot_cond.wait(min(remaining, 0.05))
            missing = [n for n in self.nodes if n not in self._boot_seen]
        if missing:
            raise StartupError(
                f"{self.port}: {', '.join(self._who(n) for n in missing)} sent no boot-up "
                f"(0x{0x700 + missing[0]:03X} data 00) within {self.config.boot_timeout:.1f} s after "
                f"NMT reset communication (000#8200); check power, node ids, the bit rate "
                f"({self.config.bitrate} bit/s) and the bus termination")

    def _configure(self, node: int) -> None:
        """Identify, check the options, write what the drive offers: mandatory objects without
        asking, optional ones after `_has` found them (the rest skipped with a note)."""
        c, lim = self.config, self.limits
        u32 = lambda value: struct.pack("<I", value)          # noqa: E731
        i16 = lambda value: struct.pack("<h", value)          # noqa: E731
        self.present[node] = {}
        self._identify(node)
        self._check_modes(node)
        self._check_polarity(node)
        max_wheel = lim.max_speed + lim.max_turn_rate * c.track_width / 2
        self._sdo_write(node, p.MODES_OF_OPERATION, 0, struct.pack("<b", p.PROFILE_VELOCITY_MODE),
                        "modes of operation")
        self._sdo_write(node, p.TARGET_VELOCITY, 0, struct.pack("<i", 0), "target velocity")
        for index, value in (
                (p.PROFILE_ACCELERATION, u32(c.accel_counts(lim.max_accel))),
                (p.PROFILE_DECELERATION, u32(c.accel_counts(max(lim.max_accel, 1e-3)))),
                (p.QUICK_STOP_DECELERATION, u32(c.accel_counts(c.quick_stop_decel))),
                (p.MAX_PROFILE_VELOCITY, u32(abs(c.to_counts(max_wheel, c.left_node)))),
                (p.QUICK_STOP_OPTION, i16(2)),              # quick-stop ramp, then switch on disabled
                (p.DISABLE_OPERATION_OPTION, i16(1)),       # disable operation brakes (slow-down ramp)
                (p.ABORT_CONNECTION_OPTION, i16(3))):       # host lost: quick stop
            self._write_optional(node, index, 0, value)
        self._map_pdo(node, 0x1400, 0x1600, p.rpdo_id(1, node), 0xFF, p.RPDO1_MAP, "RPDO1")
        self._write_optional(node, 0x1401, 1, u32(p.PDO_INVALID | p.rpdo_id(2, node)))
        self._map_pdo(node, 0x1800, 0x1A00, p.tpdo_id(1, node), p.SYNC_EVERY, p.TPDO1_MAP, "TPDO1")
        self._map_pdo(node, 0x1801, 0x1A01, p.tpdo_id(2, node), p.SYNC_EVERY, p.TPDO2_MAP, "TPDO2")
        if not self._has(node, p.PRODUCER_HEARTBEAT, 0):
            raise StartupError(f"{self._who(node)}: no producer heartbeat time 0x1017 (abort "
                               f"0x06020000); this driver supervises drives by heartbeat only "
                               f"(node guarding is not implemented)")
        self._sdo_write(node, p.PRODUCER_HEARTBEAT, 0, struct.pack("<H", c.heartbeat_ms),
                        "producer heartbeat time")
        self._write_optional(node, p.CONSUMER_HEARTBEAT, 1, u32((p.HOST_NODE << 16) | c.host_timeout_ms))
        mode = self._sdo_read(node, p.MODES_DISPLAY, 0, "modes of operation display", signed=True)
        if mode != p.PROFILE_VELOCITY_MODE:
            raise StartupError(f"{self._who(node)}: modes of operation display 0x6061 shows {mode}, "
                               f"not 3 (profile velocity) after writing 0x6060 = 3")

    def _has(self, node: int, index: int, sub: int) -> bool:
        """Does the drive have this object? An SDO upload: abort 0x06020000 or 0x06090011 = no.
        (Any other abort, e.g. write-only, means it exists.)"""
        known = self.present.setdefault(node, {})
        if (index, sub) not in known:
            try:
                self.remote[node].sdo.upload(index, sub)
                known[(index, sub)] = True
            except SdoAbortedError as exc:
                known[(index, sub)] = exc.code not in ABSENT_CODES
            except (SdoCommunicationError, can.CanError) as exc:
                raise StartupError(f"{self._who(node)}: SDO read {index:#06x}:{sub:02x} got no "
                                   f"answer within {self.config.sdo_timeout} s (2 tries): {exc}") from exc
        return known[(index, sub)]

    def _note_absent(self, node: int, index: int, sub: int) -> None:
        what = described(index, sub)
        note = f"{self._who(node)}: no {what.name} {what.key} (optional): {what.without}"
        self.startup_notes.append(note)
        log.info("%s: %s", self.port, note)

    def _write_optional(self, node: int, index: int, sub: int, value: bytes) -> bool:
        """Write an optional object where the drive has it; note it when it has not."""
        what = described(index, sub)
        assert what.need == OPTIONAL, what
        if not self._has(node, index, sub):
            self._note_absent(node, index, sub)
            return False
        self._sdo_write(node, index, sub, value, what.name)
        return True

    def _read_optional(self, node: int, index: int, sub: int = 0, signed: bool = False) -> int | None:
        if not self._has(node, index, sub):
            self._note_absent(node, index, sub)
            return None
        return self._sdo_read(node, index, sub, described(index, sub).name, signed=signed)

    def _identify(self, node: int) -> None:
        """0x1000 must say CiA 402; 0x1018 names the drive in the log (subs 2-4 where present)."""
        device_type = self._sdo_read(node, p.DEVICE_TYPE, 0, "device type")
        if device_type & 0xFFFF != 402:
            raise StartupError(f"{self._who(node)}: device type 0x1000 = {device_type:#010x} is "
                               f"device profile {device_type & 0xFFFF}, not 402 (a CiA 402 drive); "
                               f"wrong node id?")
        identity = {"vendor": self._sdo_read(node, p.IDENTITY, 1, "identity: vendor-ID")}
        for sub, key in ((2, "product"), (3, "revision"), (4, "serial")):
            if self._has(node, p.IDENTITY, sub):
                identity[key] = self._sdo_read(node, p.IDENTITY, sub, f"identity: {key}")
        self.identity[node] = identity
        log.info("%s: %s: %s", self.port, self._who(node),
                 ", ".join(f"{k} {v:#010x}" for k, v in identity.items()))

    def _check_modes(self, node: int) -> None:
        modes = self._read_optional(node, p.SUPPORTED_DRIVE_MODES)
        if modes is not None and not modes & 0x04:
            raise StartupError(f"{self._who(node)}: supported drive modes 0x6502 = {modes:#010x} "
                               f"has no profile velocity mode (bit 2); this driver needs it")

    def _check_polarity(self, node: int) -> None:
        """A wheel inverted inside the drive and again by right_mirrored turns the wrong way; one
        inverted in velocity only counts its position against its motion."""
        bits = self._read_optional(node, p.POLARITY)
        if bits is None:
            return
        velocity, position = bool(bits & 0x40), bool(bits & 0x80)
        if velocity != position:
            raise StartupError(
                f"{self._who(node)}: polarity 0x607E = {bits:#04x} inverts the "
                f"{'velocity' if velocity else 'position'} only: position actual would count "
                f"against the wheel's motion; set bits 6 and 7 alike")
        if velocity and self.config.sign(node) < 0:
            raise StartupError(
                f"{self._who(node)}: mirrored twice: the drive inverts it (polarity 0x607E = "
                f"{bits:#04x}) and the profile says right_mirrored = true; the robot would spin "
                f"when told to go straight. Set right_mirrored = false, or 0x607E = 0")
        if velocity:
            self.startup_notes.append(f"{self._who(node)}: mirrored inside the drive (0x607E = {bits:#04x})")

    def _map_pdo(self, node: int, comm: int, mapping: int, cob_id: int, kind: int,
                 entries: tuple[int, ...], what: str) -> None:
        """The remap procedure: invalidate, clear, write entries, count, type, validate. A drive
        whose mapping already is `entries` is not remapped (fixed mappings exist)."""
        u32 = lambda value: struct.pack("<I", value)          # noqa: E731
        self._sdo_write(node, comm, 1, u32(p.PDO_INVALID | cob_id), f"{what} COB-ID (invalid)")
        if self._current_mapping(node, mapping, what) != entries:
            self._sdo_write(node, mapping, 0, b"\0", f"{what} mapping count (0)")
            for sub, entry in enumerate(entries, start=1):
                self._sdo_write(node, mapping, sub, u32(entry), f"{what} mapping entry {sub}")
            self._sdo_write(node, mapping, 0, bytes((len(entries),)), f"{what} mapping count")
        self._sdo_write(node, comm, 2, bytes((kind,)), f"{what} transmission type")
        self._sdo_write(node, comm, 1, u32(cob_id), f"{what} COB-ID (valid)")

    def _current_mapping(self, node: int, mapping: int, what: str) -> tuple[int, ...]:
        count = self._sdo_read(node, mapping, 0, f"{what} mapping count")
        return tuple(self._sdo_read(node, mapping, sub, f"{what} mapping entry {sub}")
                     for sub in range(1, min(count, 8) + 1))

    def _enable(self, node: int) -> None:
        """Shutdown, switch on, enable operation, each confirmed by the statusword."""
        sw = self._sdo_read(node, p.STATUSWORD, 0, "statusword")
        for _ in range(5):
            state = p.state_of(sw)
            if state is S.OPERATION_ENABLED:
                return
            if state in (S.FAULT, S.FAULT_REACTION_ACTIVE):
                if self.reset_faults_on_open:
                    self.reset_faults()
                    sw = self._sdo_read(node, p.STATUSWORD, 0, "statusword")
                    continue
                raise StartupError(f"{self._who(node)} is in Fault (statusword {sw:#06x}, "
                                   f"{self._fault_text(node)}); a fault is cleared only on purpose: "
                                   f"reset_faults(), or the driver option reset_faults = true")
            if state not in p.ENABLE_STEPS:
                raise StartupError(f"{self._who(node)}: statusword {sw:#06x} shows "
                                   f"{state.value if state else 'no CiA 402 state'}; cannot enable")
            command, expected = p.ENABLE_STEPS[state]
            self._sdo_write(node, p.CONTROLWORD, 0, struct.pack("<H", command),
                            f"controlword {command.name.lower().replace('_', ' ')}")
            sw = self._expect_state(node, expected, f"controlword {int(command):#06x}")
        raise StartupError(f"{self._who(node)}: not in operation enabled after 5 steps "
                           f"(statusword {sw:#06x})")

    def _expect_state(self, node: int, expected, why: str) -> int:
        deadline = time.monotonic() + self.config.state_timeout
        while True:
            sw = self._sdo_read(node, p.STATUSWORD, 0, "statusword")
            if p.state_of(sw) is expected:
                return sw
            if time.monotonic() >= deadline:
                shown = p.state_of(sw)
                raise StartupError(f"{self._who(node)}: {why} should lead to '{expected.value}' but "
                                   f"the statusword 0x6041 stayed {sw:#06x} "
                                   f"({shown.value if shown else 'no CiA 402 state'}) for "
                                   f"{self.config.state_timeout} s")
            time.sleep(0.01)

    # -- the start-up self-check ---------------------------------------------------------------------
    def _self_check(self) -> None:
        """Move each wheel a little forward by the profile's reckoning and read its encoder back.
        Refuses, before anything drives, a profile whose units, gear or mirroring contradict what
        the drive reports: velocity or position against the command, or off by a factor."""
        c = self.config
        self.self_check_result = {}
        if not c.self_check:
            self.startup_notes.append("self-check off (self_check = false): units and polarity unchecked")
            return
        run_time = c.self_check_distance / SELF_CHECK_SPEED
        if not self.simulated and self._world_step is not None and self.clock is not None:
            self._world_step(self.clock.now())     # a real-time simulation: its world up to now first
        self.odometry.reset()
        positions = self._odometry_by_sdo()          # the robot moves: odometry follows it
        for node in self.nodes:
            start = positions[node]
            self._sdo_write(node, p.TARGET_VELOCITY, 0,
                            struct.pack("<i", c.to_counts(SELF_CHECK_SPEED, node)), "target velocity (self-check)")
            t_on = self._time()
            try:
                self._pause(run_time * 0.6)
                velocity = c.velocity_mps(self._sdo_read(node, p.VELOCITY_ACTUAL, 0, "velocity actual value",
                                                         signed=True), node)
                self._pause(max(0.0, run_time - (self._time() - t_on)))
            finally:
                self._sdo_write(node, p.TARGET_VELOCITY, 0, struct.pack("<i", 0), "target velocity")
            expected = SELF_CHECK_SPEED * (self._time() - t_on)    # as long as it really ran
            self._wait_standstill(c.stop_timeout, lambda n=node: {n: self._sdo_velocity(n)})
            positions = self._odometry_by_sdo()
            travel = c.travel_metres(wrap_delta(positions[node], start), node)
            self.self_check_result[node] = {"commanded_mps": SELF_CHECK_SPEED, "velocity_mps": velocity,
                                            "expected_m": expected, "travel_m": travel}
            self._judge_self_check(node, velocity, travel, expected)

    def _odometry_by_sdo(self) -> dict[int, int]:
        """Both position counters read by SDO, fed to odometry (no PDOs before driving)."""
        positions = {n: self._sdo_read(n, p.POSITION_ACTUAL, 0, "position actual value", signed=True)
                     for n in self.nodes}
        self.odometry.update(positions[self.config.left_node], positions[self.config.right_node])
        return positions

    def _sdo_velocity(self, node: int) -> float:
        units = self._sdo_read(node, p.VELOCITY_ACTUAL, 0, "velocity actual value", signed=True)
        return self.config.velocity_mps(units, node)

    def _judge_self_check(self, node: int, velocity: float, travel: float, expected: float) -> None:
        c = self.config
        low, high = PLAUSIBLE
        units = (f"velocity_unit = {c.velocity_unit!r} x {c.velocity_resolution}, position_unit = "
                 f"{c.position_unit!r} x {c.position_resolution}, encoder_counts = {c.encoder_counts}, "
                 f"gear_ratio = {c.gear_ratio}, wheel_radius = {c.wheel_radius}")
        head = (f"{self._who(node)}: start-up self-check: commanded {SELF_CHECK_SPEED:.3f} m/s forward "
                f"for {expected * 1000:.0f} mm")
        if velocity <= 0 or travel <= 0:
            which = ("velocity actual 0x606C" if velocity <= 0 else "position actual 0x6064")
            raise StartupError(f"{head}, but its {which} ran backwards (velocity {velocity:+.3f} m/s, "
                               f"travel {travel * 1000:+.1f} mm by the profile's reckoning): the drive's "
                               f"feedback contradicts its command or the profile's mirroring "
                               f"(right_mirrored = {str(c.right_mirrored).lower()}); check the "
                               f"drive's polarity 0x607E and the mounting, wheels off the ground")
        if not low <= velocity / SELF_CHECK_SPEED <= high:
            raise StartupError(f"{head}; the drive reports {velocity:.3f} m/s: the velocity units "
                               f"disagree by x{velocity / SELF_CHECK_SPEED:.2f} ({units})")
        if not low <= travel / expected <= high:
            raise StartupError(f"{head}; its encoder says {travel * 1000:.1f} mm: velocity and position "
                               f"units disagree by x{travel / expected:.2f} ({units})")

    # -- waiting, and stopping as a drive manual says --------------------------------------------------
    def _pause(self, seconds: float) -> None:
        """Let `seconds` pass for the drives: real time sleeps; a simulated clock steps the world
        cycle by cycle (host heartbeat, SYNC while streaming, every frame handled)."""
        end = self._time() + seconds
        while True:
            now = self._time()
            if now >= end - 1e-9:
                return
            step = min(self.config.sync_period, end - now)
            if self.simulated:
                stepped = self.clock.advance(step)
                if self._world_step is not None:
                    self._world_step(stepped)
                self._lockstep_cycle()
            else:
                time.sleep(step)
                if self._world_step is not None and self.clock is not None:
                    self._world_step(self.clock.now())     # a real-time simulation: its world

    def _wait_for(self, done, timeout: float) -> bool:
        """Pause cycle by cycle until `done()` or `timeout` s; whether it came true."""
        deadline = self._time() + timeout
        while True:
            self._pause(self.config.sync_period)
            if done():
                return True
            if self._time() >= deadline:
                return False

    def _wait_standstill(self, timeout: float, speeds=None) -> bool:
        """Until every wheel's velocity actual is within `standstill_window`, or `timeout` s.
        `speeds()` gives {node: m/s}; default: the TPDOs, counted fresh only after two cycles."""
        window = self.config.standstill_window
        first = dict(self._vel_seen)

        def still() -> bool:
            if speeds is not None:
                current = speeds()
            else:
                heard = self._heard()
                if any(self._vel_seen[n] < first[n] + 2 for n in heard):
                    return False
                current = {n: self.config.velocity_mps(self._vel[n], n) for n in heard}
            return all(abs(v) <= window for v in current.values())
        return self._wait_for(still, timeout)

    def _stop_by_sdo(self) -> None:
        """A start-up that failed after enabling (no PDOs yet): the same steps by SDO."""
        def each(word: int) -> None:
            for node in self.nodes:
                try:
                    self._sdo_write(node, p.TARGET_VELOCITY, 0, struct.pack("<i", 0), "target velocity")
                    self._sdo_write(node, p.CONTROLWORD, 0, struct.pack("<H", word), "controlword")
                except StartupError as exc:
                    log.warning("%s: %s", self.port, exc)

        def speeds() -> dict[int, float]:
            try:
                return {n: self._sdo_velocity(n) for n in self.nodes}
            except StartupError:
                return {}
        each(p.Cw.QUICK_STOP)
        self._wait_standstill(self.config.stop_timeout, speeds)
        each(p.Cw.DISABLE_VOLTAGE)
        self._powered = False

    def _heard(self) -> list[int]:
        """The drives whose heartbeat is fresh: a silent one cannot be waited for."""
        limit = self.config.heartbeat_timeout_ms / 1000.0
        now = self._time()
        return [n for n in self.nodes if now - self._heartbeat_t.get(n, -math.inf) <= limit]

    def _stop_drives(self, why: str) -> None:
        """Quick stop (0x605A = 2: the quick-stop ramp), wait for standstill or `stop_timeout`,
        disable operation (braking, 0x605C = 1, for a drive the quick stop left enabled), then
        disable voltage. SYNC goes on throughout, so odometry sees the whole stopping distance."""
        with self._lock:
            if self.network is None or not (self._enabled or self._streaming or self._powered):
                return
            if not (self._enabled or self._streaming):
                self._stop_by_sdo()
                return
            record = {"why": why, "t_quick_stop": time.monotonic()}
            self._enabled = False
            self.watchdog.disarm()
            self._cmd = (0, 0)
            self._controlword = p.Cw.QUICK_STOP
            self._streaming = True
            self._send_targets()
        record["standstill"] = self._wait_standstill(self.config.stop_timeout)
        record["t_standstill"] = time.monotonic()
        with self._lock:
            self._controlword = p.Cw.SWITCH_ON         # disable operation
            self._send_targets()
        self._wait_for(lambda: not any(p.state_of(self._sw[n]) is S.OPERATION_ENABLED
                                       for n in self._heard()), self.config.stop_timeout)
        with self._lock:
            self._controlword = p.Cw.DISABLE_VOLTAGE
            self._send_targets()
            self._streaming = self._powered = False
        record["t_disabled"] = time.monotonic()
        record["states"] = {n: (p.state_of(self._sw[n]).value if p.state_of(self._sw[n]) else "?")
                            for n in self.nodes}
        self.stop_log.append(record)
        log.info("%s: stopped (%s): %s", self.port, why,
                 "standstill" if record["standstill"] else f"no standstill within {self.config.stop_timeout} s")

    # -- SDO through canopen, with errors that name node, object and cause ----------------------
    def _sdo_write(self, node: int, index: int, sub: int, value: bytes, what: str,
                   missing_ok: bool = False) -> None:
        try:
            self.remote[node].sdo.download(index, sub, value)
        except SdoAbortedError as exc:
            if missing_ok and exc.code in (0x06020000, 0x06090011):
                return
            raise StartupError(
                f"{self._who(node)}: SDO write {index:#06x}:{sub:02x} ({what}) = 0x{value[::-1].hex()} "
                f"refused: abort code {exc.code:#010x}, {p.abort_meaning(exc.code)}") from exc
        except (SdoCommunicationError, can.CanError) as exc:
            raise StartupError(
                f"{self._who(node)}: SDO write {index:#06x}:{sub:02x} ({what}) got no answer within "
                f"{self.config.sdo_timeout} s (2 tries): {exc}; is the drive powered and in "
                f"pre-operational or operational?") from exc

    def _sdo_read(self, node: int, index: int, sub: int, what: str, signed: bool = False) -> int:
        try:
            data = self.remote[node].sdo.upload(index, sub)
        except SdoAbortedError as exc:
            raise StartupError(f"{self._who(node)}: SDO read {index:#06x}:{sub:02x} ({what}) refused: "
                               f"abort code {exc.code:#010x}, {p.abort_meaning(exc.code)}") from exc
        except (SdoCommunicationError, can.CanError) as exc:
            raise StartupError(f"{self._who(node)}: SDO read {index:#06x}:{sub:02x} ({what}) got no "
                               f"answer within {self.config.sdo_timeout} s (2 tries): {exc}") from exc
        return int.from_bytes(data, "little", signed=signed)

    # -- sending ---------------------------------------------------------------------------------
    def _send(self, can_id: int, data: bytes) -> None:
        network = self.network
        if network is None:
            return
        network.send_message(can_id, data)

    def _send_targets(self) -> None:
        """RPDO1 to both drives with the current command (caller holds the lock)."""
        try:
            for node, target in zip(self.nodes, self._cmd):
                self._send(*p.rpdo1(node, self._controlword, target))
                self.stats["rpdos"] += 1
                self.rpdo_times.append((time.monotonic(), node, target))
            if len(self.rpdo_times) > 20_000:
                del self.rpdo_times[:10_000]
        except can.CanError as exc:
            self._raise_fault(f"CAN send failed: {exc} (bus-off or adapter unplugged?)")

    def _send_sync(self) -> None:
        try:
            self._send(*p.sync())
            self.stats["syncs"] += 1
        except can.CanError as exc:
            self._raise_fault(f"CAN send failed (SYNC): {exc}")

    def _send_host_heartbeat(self) -> None:
        try:
            self._send(*p.heartbeat(p.HOST_NODE, p.NodeState.OPERATIONAL))
        except can.CanError as exc:
            self._raise_fault(f"CAN send failed (heartbeat): {exc}")

    def _on_stale(self) -> None:
        """Watchdog: no fresh command for WATCHDOG s -> zero, once."""
        with self._lock:
            if self.watchdog.armed:
                return
            self._cmd = (0, 0)
            self.stats["watchdog_stops"] += 1
            if self._enabled:
                self._send_targets()
                self.fault_log.append({"reason": "watchdog", "t_zero": time.monotonic()})

    # -- receiving (canopen's notifier thread) --------------------------------------------------------
    def _on_heartbeat(self, can_id: int, data: bytes, timestamp: float) -> None:
        node = can_id - p.HEARTBEAT_BASE
        try:
            state = p.decode_heartbeat(bytes(data))
        except Exception as exc:
            self.last_error = str(exc)
            return
        if state is p.NodeState.BOOT_UP:
            with self._boot_cond:
                self._boot_seen[node] = self._time()
                self._boot_cond.notify_all()
            if self._enabled:
                self._raise_fault(f"{self._who(node)} rebooted (boot-up frame) during operation")
            return
        self._heartbeat_t[node] = self._time()
        if self._enabled and state is not p.NodeState.OPERATIONAL:
            self._raise_fault(f"{self._who(node)} left NMT operational (heartbeat state {state.name})")

    def _on_emcy(self, can_id: int, data: bytes, timestamp: float) -> None:
        node = can_id - p.EMCY_BASE
        try:
            emcy = p.decode_emcy(bytes(data))
        except Exception as exc:
            self.last_error = str(exc)
            return
        self.stats["emcys"] += 1
        self.emcy_log.append((node, emcy))
        if emcy.code == 0:
            return
        self._raise_fault(f"{self._who(node)}: EMCY {emcy.code:#06x} {emcy.meaning} "
                          f"(error register {emcy.register:#04x})",
                          {"device": self._who(node), "code": emcy.code, "meaning": emcy.meaning})

    def _on_tpdo1(self, can_id: int, data: bytes, timestamp: float) -> None:
        node = can_id - p.TPDO_BASE[0]
        try:
            sw, vel = p.decode_tpdo1(bytes(data))
        except Exception as exc:
            self.last_error = str(exc)
            return
        self.stats["tpdos"] += 1
        self._sw[node], self._vel[node] = sw, vel
        self._vel_seen[node] += 1
        if self._enabled:
            state = p.state_of(sw)
            if sw & p.SW_FAULT:
                self._raise_fault(f"{self._who(node)}: statusword {sw:#06x} has the fault bit "
                                  f"({state.value if state else '?'})")
            elif state is not S.OPERATION_ENABLED:
                self._raise_fault(f"{self._who(node)} left operation enabled: statusword {sw:#06x} "
                                  f"({state.value if state else '?'})")

    def _on_tpdo2(self, can_id: int, data: bytes, timestamp: float) -> None:
        node = can_id - p.TPDO_BASE[1]
        try:
            position = p.decode_tpdo2(bytes(data))
        except Exception as exc:
            self.last_error = str(exc)
            return
        self.stats["tpdos"] += 1
        with self._lock:
            self._pos[node] = position
            self._pos_seen[node] += 1
            cycle = min(self._pos_seen.values())
            if cycle <= self._cycle_done:
                return
            self._cycle_done = cycle
            self.stats["cycles"] += 1
            self._publish()
            if not self.simulated and self._streaming:
                self._send_targets()          # the control cycle: TPDOs in, RPDOs out

    def _on_sonar(self, can_id: int, data: bytes, timestamp: float) -> None:
        first = (can_id - self.config.sonar_node - 0x180) // 0x100 * 4
        ranges = list(self._sonar)
        for k, (mm,) in enumerate(struct.iter_unpack("<H", bytes(data[: len(data) // 2 * 2]))):
            if first + k < len(ranges):
                ranges[first + k] = math.inf if mm in (0, 0xFFFF) else mm / 1000.0
        self._sonar = tuple(ranges)
        self._sonar_t = self._time()

    def _publish(self) -> None:
        c = self.config
        left, right = c.left_node, c.right_node
        x, y, th = self.odometry.update(self._pos[left], self._pos[right])
        v, w = c.body_speeds(c.velocity_mps(self._vel[left], left), c.velocity_mps(self._vel[right], right))
        enabled = all(p.state_of(self._sw[n]) is S.OPERATION_ENABLED for n in self.nodes)
        up = self._fault is None and self._enabled
        state = BaseState(t=self._now(), x=x, y=y, th=th, v=v, w=w, sonar=self._sonar,
                          motors_enabled=enabled, link_up=up, extra=self._extra())
        with self._state_cond:
            self._state = state
            self._state_cond.notify_all()

    def _extra(self) -> dict:
        info = self._fault_info
        return {"fault": self._fault or "", "fault_device": info.get("device", ""),
                "fault_code": info.get("code"), "fault_meaning": info.get("meaning", ""),
                "bus": self.bus_state,
                "statusword": {n: self._sw[n] for n in self.nodes},
                "watchdog_stops": self.stats["watchdog_stops"], "cycles": self.stats["cycles"]}

    def wait_for_cycle(self, after: int, timeout: float) -> bool:
        """Block until more than `after` SYNC cycles were decoded (benchmarks and tests)."""
        with self._state_cond:
            return self._state_cond.wait_for(lambda: self.stats["cycles"] > after, timeout)

    def on_bus_error(self, state: str) -> None:
        self.bus_state = state
        if state in ("error-passive", "bus-off"):
            self._raise_fault(f"CAN bus {state} (reported by the CAN controller)")

    # -- faults --------------------------------------------------------------------------------------
    def _raise_fault(self, reason: str, info: dict | None = None) -> None:
        """Record a fault (`info`: device, code, meaning, where known); act at once in real
        time, in the next poll() in lock-step."""
        with self._lock:
            self._pending_faults.append((reason, time.monotonic(), info))
            if not self.simulated:
                self._act_on_faults()

    def _act_on_faults(self) -> None:
        with self._lock:
            pending, self._pending_faults = self._pending_faults, []
            for reason, t_event, info in pending:
                if self._fault is None:
                    self._fault = reason
                    self._fault_info = info or {"device": "CAN base", "meaning": reason}
                    log.warning("%s: fault: %s", self.port, reason)
                else:
                    log.info("%s: further fault: %s", self.port, reason)
                self.stats["faults"] += 1
                was_enabled = self._enabled
                self._enabled = False
                self._cmd = (0, 0)
                self.watchdog.disarm()
                t_zero = None
                self._controlword = p.Cw.QUICK_STOP   # from now on every RPDO1: quick stop, target 0
                self._streaming = self._streaming or was_enabled   # SYNC, odometry go on
                try:
                    for node in self.nodes:           # stop both wheels at once
                        self._send(*p.rpdo1(node, p.Cw.QUICK_STOP, 0))
                    t_zero = time.monotonic()
                except can.CanError as exc:
                    self.last_error = f"could not send the quick stop: {exc}"
                self.fault_log.append({"reason": reason, "t_event": t_event, "t_zero": t_zero,
                                       "was_enabled": was_enabled})
            if pending:
                self.last_error = self._fault or ""
                self._set_link(False)

    def _supervise(self, now: float) -> None:
        with self._lock:
            if self._enabled:
                limit = self.config.heartbeat_timeout_ms / 1000.0
                for node in self.nodes:
                    age = now - self._heartbeat_t.get(node, now)
                    if age > limit:
                        other = [self.config.wheel_name(n) for n in self.nodes if n != node]
                        self._pending_faults.append((
                            f"{self._who(node)}: no heartbeat for {age:.2f} s (time-out "
                            f"{limit:.2f} s); link down, stopped the {', '.join(other)}",
                            time.monotonic(),
                            {"device": self._who(node), "code": None,
                             "meaning": f"heartbeat lost (none for {age:.2f} s, time-out {limit:.2f} s)"}))
                silent = now - self._sonar_t
                if self.config.sonar_node and self.config.sonars and silent > limit:
                    who = f"node {self.config.sonar_node} (sonar board)"
                    self._pending_faults.append((
                        f"{who}: no ranges for {silent:.2f} s; its silence would read as free "
                        f"space ahead", time.monotonic(),
                        {"device": who, "code": None, "meaning": f"sonar board silent for {silent:.2f} s"}))
            if self._pending_faults:
                self._act_on_faults()

    def _drain(self, deadline: float) -> None:
        if not self.lockstep.to_host.wait_drained(max(0.0, deadline - time.monotonic())):
            self.last_error = "emulator frames did not arrive in time"

    def _cycle_loop(self) -> None:
        """Real time: SYNC every sync_period, heartbeat, supervision, bus state."""
        c = self.config
        next_sync = time.monotonic()
        next_heartbeat = next_sync
        while not self._closing.is_set():
            now = time.monotonic()
            if now >= next_heartbeat:
                self._send_host_heartbeat()
                next_heartbeat += c.host_heartbeat_ms / 1000.0
                if next_heartbeat < now:
                    next_heartbeat = now + c.host_heartbeat_ms / 1000.0
            if now >= next_sync:
                if self._streaming:
                    self._send_sync()
                next_sync += c.sync_period
                if next_sync < now:
                    next_sync = now + c.sync_period
            self._supervise(now)
            if now >= self._next_bus_check:
                self._next_bus_check = now + BUS_STATE_EVERY
                self._check_bus_state()
            wait = min(next_sync, next_heartbeat) - time.monotonic()
            if wait > 0:
                self._closing.wait(wait)

    def _check_bus_state(self) -> None:
        bus = getattr(self.network, "bus", None)
        try:
            state = bus.state if bus is not None else None
        except Exception:
            return
        if state == can.BusState.PASSIVE and self.bus_state != "error-passive":
            self.on_bus_error("error-passive")
        elif state == can.BusState.ERROR and self.bus_state != "bus-off":
            self.on_bus_error("bus-off")

    def _set_link(self, up: bool) -> None:
        with self._state_cond:
            self._state = replace(self._state, link_up=up, t=self._now(),
                                  v=self._state.v if up else 0.0, w=self._state.w if up else 0.0,
                                  extra=self._extra())
            self._state_cond.notify_all()

    @property
    def link_up(self) -> bool:
        return self._state.link_up

    @property
    def fault(self) -> str | None:
        return self._fault


def _close(word: str, known) -> str:
    import difflib
    close = difflib.get_close_matches(word, sorted(known), n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


class _Raw(can.Listener):
    """Error frames (canopen ignores them) -> the bus state."""

    def __init__(self, base: CanOpenBase) -> None:
        self.base = base

    def on_message_received(self, msg: can.Message) -> None:
        if msg.is_error_frame:
            state = p.decode_error_frame(msg.arbitration_id, bytes(msg.data))
            if state is not None:
                self.base.on_bus_error(state)
        if self.base.can_log is not None:
            self.base.can_log.write(msg)
