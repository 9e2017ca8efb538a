"""The CAN base driver: a differential drive with two CiA 402 drives, through python-can.

(The start-up configuration and self-check are in `robots.canopen.startup`, the stop sequence
in `robots.canopen.stopping`; both are mixins of `CanOpenBase`.)

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
the SYNC in sim time and handles (frames counted by `LockStep`) every frame the emulator sent,
so a `--fast` run is deterministic; nor does a receiving thread: the frames are read on the
caller's thread around each send and in `poll()` (`robots.canopen.bus.LockStepReceiver`). In
real time a cycle thread sends SYNC and the heartbeat, the RPDOs follow each cycle's TPDOs,
and the watchdog has its thread.
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
from robots.canopen.startup import DriveStartUp, StartupError
from robots.canopen.stopping import DriveStopping
from robots.canopen.bus import CandumpLog, Counted, DriverBus, LockStepReceiver, open_bus, parse_port
from robots.canopen.od import drive_dictionary
from robots.canopen.wheels import DriveConfig, Odometry
from robots.link.arrival import StampedArrival
from robots.link.lockstep import LockStep
from robots.link.watchdog import CommandWatchdog
from robots.profile import Limits

log = logging.getLogger(__name__)
S = p.State402
WATCHDOG = 0.15             # s without a fresh command -> zero
BUS_STATE_EVERY = 0.5       # s between polls of the interface's error state (real time)
LOG_ENV = "INTERBOT_CAN_LOG"
NOTIFIER_CYCLE = 0.05       # s, longest the receive thread blocks (canopen's default is 1 s)


class CanOpenBase(DriveStartUp, DriveStopping, Base):
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
        self.receiver: LockStepReceiver | None = None   # lock-step: the bus read on our thread
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
        self._heartbeat_t: dict[int, float] = {}     # when each drive's newest heartbeat arrived
        self._stamps = StampedArrival()               # a frame's arrival from its bus stamp
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
        # the laser, for the self-check's witness of the robot's real turn (robots.scan_turn):
        # a callable giving the newest LaserScan, set by whoever opens the robot before open()
        self.scan_source = None
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

    def _arrival(self, timestamp: float) -> float:
        """Supervision time a received frame arrived: from its bus stamp in real time (a
        backlog of old frames behind a flood never counts as fresh), now in lock-step."""
        if self.simulated:
            return self._time()
        return self._stamps.arrived(timestamp, time.time(), time.monotonic())

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
        self.receiver = None
        network = canopen.Network()
        network.NOTIFIER_CYCLE = NOTIFIER_CYCLE          # close() returns promptly
        network.bus = DriverBus(bus, self.lockstep.to_device if self.lockstep else None, self.can_log,
                                deliver=self.lockstep.deliver if self.lockstep else None)
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
        if self._reads_on_own_thread():
            self.receiver = LockStepReceiver(network.bus, network.listeners, self.lockstep.to_host)
            network.bus.receive = self.receiver.receive
            network.send_lock = threading.RLock()   # a listener may answer within the send
        else:
            network.connect()                       # python-can's Notifier thread reads the bus
        self.network = network

    def _reads_on_own_thread(self) -> bool:
        """Lock-step on the in-process virtual bus: the emulator's frames are queued there by
        the time our `send` returns, so this thread reads them (`LockStepReceiver`). Anywhere
        else (real time, socketcand, an adapter) frames arrive on their own time: a Notifier."""
        return self.lockstep is not None and self.simulated and self.spec.interface == "virtual"

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
            self._raise_fault(f"CAN send failed: {exc} (bus-off or adapter unplugged?)", self._link_info(exc))

    def _send_sync(self) -> None:
        try:
            self._send(*p.sync())
            self.stats["syncs"] += 1
        except can.CanError as exc:
            self._raise_fault(f"CAN send failed (SYNC): {exc}", self._link_info(exc))

    def _send_host_heartbeat(self) -> None:
        try:
            self._send(*p.heartbeat(p.HOST_NODE, p.NodeState.OPERATIONAL))
        except can.CanError as exc:
            self._raise_fault(f"CAN send failed (heartbeat): {exc}", self._link_info(exc))

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

    # -- receiving (canopen's notifier thread; in lock-step the caller's: LockStepReceiver) ------------
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
        self._heartbeat_t[node] = max(self._heartbeat_t.get(node, -math.inf), self._arrival(timestamp))
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
        self._sonar_t = max(self._sonar_t, self._arrival(timestamp))

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
            self._raise_fault(f"CAN bus {state} (reported by the CAN controller)",
                              {"device": f"CAN bus {self.port.split('?')[0]}", "code": None,
                               "meaning": f"the CAN controller is {state}"})

    def on_link_lost(self, exc: Exception) -> None:
        if self._closing.is_set():
            return
        self._raise_fault(f"CAN link lost while receiving: {exc}", self._link_info(exc, "receiving"))

    # -- faults --------------------------------------------------------------------------------------
    def _link_info(self, exc: Exception, doing: str = "sending") -> dict:
        return {"device": f"CAN link {self.port.split('?')[0]}", "code": None, "meaning": f"{doing} failed: {exc}"}

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
        """Until every frame the emulator sent is handled: read here, or waited for."""
        timeout = max(0.0, deadline - time.monotonic())
        if self.receiver is not None:
            done = self.receiver.drain(timeout)
        else:
            done = self.lockstep.to_host.wait_drained(timeout)
        if not done:
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

    def on_error(self, exc: Exception) -> None:
        """The receive thread lost the link: a link fault, like a failed send."""
        self.base.on_link_lost(exc)

    def on_message_received(self, msg: can.Message) -> None:
        if msg.is_error_frame:
            state = p.decode_error_frame(msg.arbitration_id, bytes(msg.data))
            if state is not None:
                self.base.on_bus_error(state)
        if self.base.can_log is not None:
            self.base.can_log.write(msg)
