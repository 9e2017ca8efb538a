"""Two emulated CiA 402 wheel drives (and a sonar board) on a CAN bus, around the simulated body.

Each `Drive` (robots.canopen.drive) is a CiA 402 device on this emulator's python-can bus;
here: the bus, the wheels following the simulated body, the sonar board, and the faults a
test injects.

Faults it produces: EMCY 0x2310 over-current when the wheels push against an obstacle that
holds the body (0.5 s), EMCY 0x8611 on following error (a wheel lags its demand by more than
0.25 m/s for 1 s), EMCY 0x8130 and a quick stop when the host's heartbeat stops, and whatever
a test injects (`inject_fault`, `power_off`, `bus_error`). Knobs for start-up tests: per drive
`sdo_delay` (a slow drive), `refuse` {(index, sub): abort code}, `boot_delay` (None = never).

Time: in lock-step (`LockStep` given, simulated clock) the world's step hook moves the wheels
and runs the timers in sim time, and each frame the driver sends is counted as taken only
after it was handled, so a `--fast` run is deterministic. In real time `start_clock()` runs
the timers (and, standing alone, the world) in a thread.
"""
from __future__ import annotations

import itertools
import logging
import math
import struct
import threading
import time

import can
import canopen

from robots.canopen import protocol as p
from robots.canopen.bus import Counted, DriverBus
from robots.canopen.drive import Drive
from robots.canopen.wheels import DriveConfig
from robots.link.lockstep import LockStep

log = logging.getLogger(__name__)
S = p.State402
SONAR_CYCLE = 0.05           # s between the sonar board's readings
STALL_TIME = 0.5             # s pushing against an obstacle before the current limit trips
STALL_DEMAND = 0.05          # m/s of demand that counts as pushing
_channels = itertools.count(1)
class CanOpenEmulator:
    """The drives (and sonar board) on a python-can bus, moving `world.body`."""

    name = "canopen-emulator"

    def __init__(self, world, config: DriveConfig, clock=None, lockstep: LockStep | None = None,
                 channel: str | None = None, boot_delays: dict[int, float | None] | None = None,
                 port: str | None = None) -> None:
        self.world = world
        self.config = config
        self.clock = clock
        self.lockstep = lockstep
        self.channel = channel or f"interbot-can-{next(_channels)}"
        self.lock = threading.RLock()
        boot = boot_delays or {}
        self.drives = {n: Drive(self, n, boot.get(n, 0.0)) for n in (config.left_node, config.right_node)}
        self.sonar_powered = True                # tests: False = the sonar board goes silent
        self.mirrored: dict[int, bool] = {}      # tests: how a motor is really mounted, if not as profiled
        self.sent = 0
        self.network = canopen.Network()
        self.network.NOTIFIER_CYCLE = 0.05                # close() returns promptly
        if port is not None:             # a real (v)can interface, e.g. socketcan:vcan0
            from robots.canopen.bus import open_bus, parse_port
            spec = parse_port(port)
            self.channel = spec.channel
            self.bus = open_bus(spec, config.bitrate)
        else:
            self.bus = can.Bus(interface="virtual", channel=self.channel)
        self.network.bus = DriverBus(self.bus, lockstep.to_host if lockstep else None, wait=False)
        if lockstep is not None:
            self.network.listeners.append(Counted(lockstep.to_device))
        for drive in self.drives.values():
            drive.attach(self.network)
        self.network.subscribe(p.SYNC_ID, self._on_sync_sonar)
        self._pump_lock = threading.Lock()
        if lockstep is not None and port is None:
            lockstep.pump = self._pump           # the driver's thread hands us its frames
        else:
            self.network.connect()               # a notifier thread reads the bus
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._servers: list = []
        self._hooked = False
        self._sonar: list[float] = [math.inf] * config.sonars
        self._sonar_due = 0.0
        self._stalled_since: float | None = None
        self.timers(self.now())

    @classmethod
    def for_profile(cls, profile, world, clock=None, lockstep=None, **kw) -> "CanOpenEmulator":
        return cls(world, DriveConfig.from_options(profile.base.options, f"{profile.source} [base]"),
                   clock=clock, lockstep=lockstep, **kw)

    # -- bus ----------------------------------------------------------------------------------
    def send(self, can_id: int, data: bytes) -> None:
        """Every frame leaves through `network.bus`, which counts it for lock-step."""
        try:
            self.network.send_message(can_id, data)
            self.sent += 1
        except can.CanError as exc:
            log.warning("emulator: could not send %03X: %s", can_id, exc)

    def _pump(self, timeout: float) -> None:
        """Lock-step on the in-process bus: read the frames that have arrived (waiting up to
        `timeout` s for the first) and hand each to the listeners in order, as python-can's
        notifier thread would, but on the caller's thread (`LockStep.deliver`, called by the
        driver's `send`): no thread hand-over per frame. One caller at a time keeps the order."""
        bus = self.network.bus
        with self._pump_lock:
            msg = bus.recv(timeout)
            while msg is not None:
                for listener in self.network.listeners:
                    listener.on_message_received(msg)
                msg = bus.recv(0.0)

    def now(self) -> float:
        if self.lockstep is not None or self.clock is None:
            return float(self.world.t)
        return self.clock.now()

    # -- the world -------------------------------------------------------------------------------
    def attach(self, simulation) -> None:
        if not self._hooked:
            simulation.on_step(self._on_world_step)
            self._hooked = True

    def _on_world_step(self, world, dt: float) -> None:
        self.physics(dt)
        if self.lockstep is not None:
            self.timers(world.t)

    def physics(self, dt: float) -> None:
        """Wheels follow the body; the body is commanded from the drives' demands."""
        c = self.config
        body = self.world.body
        left, right = c.wheel_speeds(body.v, body.w)
        with self.lock:
            lf, rt = self.drives[c.left_node], self.drives[c.right_node]
            lf.ramp(dt, c, left, self.mount(c.left_node))
            rt.ramp(dt, c, right, self.mount(c.right_node))
            demand_l = lf.wheel_demand(c, self.mount(c.left_node))
            demand_r = rt.wheel_demand(c, self.mount(c.right_node))
        body.set_command(*c.body_speeds(demand_l, demand_r))
        self._check_stall(body, demand_l, demand_r)
        if c.sonar_node and c.sonars and self.world.t + 1e-9 >= self._sonar_due:
            self._sonar = [float(r) for r in self.world.sonar_ranges()][:c.sonars]
            self._sonar_due = self.world.t + SONAR_CYCLE

    def mount(self, node: int) -> int:
        """-1 where the motor is mounted mirrored (the truth: `mirrored`, else the profile's)."""
        mirrored = self.mirrored.get(node, node == self.config.right_node and self.config.right_mirrored)
        return -1 if mirrored else 1

    def _check_stall(self, body, demand_l: float, demand_r: float) -> None:
        """A body held by an obstacle while the wheels push: over-current on the pushing drives."""
        pushing = [n for n, d in ((self.config.left_node, demand_l), (self.config.right_node, demand_r))
                   if abs(d) > STALL_DEMAND]
        if not (body.stalled and pushing):
            self._stalled_since = None
            return
        now = self.now()
        if self._stalled_since is None:
            self._stalled_since = now
        elif now - self._stalled_since >= STALL_TIME:
            self._stalled_since = None
            with self.lock:
                for node in pushing:
                    if self.drives[node].state is S.OPERATION_ENABLED:
                        self.drives[node].fault(0x2310)

    def timers(self, now: float) -> None:
        with self.lock:
            for drive in self.drives.values():
                drive.timers(now)

    def start_clock(self, simulation=None, period: float = 0.005) -> None:
        """Real time: timers (and the world, when standing alone) in a thread."""
        def run() -> None:
            while not self._stop.wait(period):
                now = self.clock.now() if self.clock is not None else time.monotonic()
                if simulation is not None:
                    simulation.advance(now)
                self.timers(now)
        self._thread = threading.Thread(target=run, name="canopen-emulator-clock", daemon=True)
        self._thread.start()

    # -- the sonar board ----------------------------------------------------------------------
    def _on_sync_sonar(self, can_id: int, data: bytes, timestamp: float) -> None:
        node, count = self.config.sonar_node, self.config.sonars
        if not node or not count or not self.sonar_powered:
            return
        with self.lock:
            ranges = list(self._sonar)
        millimetres = [0xFFFF if not math.isfinite(r) else min(0xFFFE, round(r * 1000)) for r in ranges]
        for k in range(0, len(millimetres), 4):
            chunk = millimetres[k:k + 4]
            self.send(p.TPDO_BASE[k // 4] + node, struct.pack(f"<{len(chunk)}H", *chunk))

    # -- faults for tests --------------------------------------------------------------------------
    def inject_fault(self, node: int, code: int = 0x2310) -> None:
        """The drive detects `code` (default over-current): EMCY, then Fault."""
        with self.lock:
            self.drives[node].fault(code)

    def power_off(self, node: int) -> None:
        """The drive goes silent (no heartbeat, no answers); its motor coasts to a stop."""
        with self.lock:
            drive = self.drives[node]
            drive.powered = False
            drive.booted = False
            drive._reset_application()
            drive._reset_communication()
            drive.node.data_store.clear()

    def power_on(self, node: int) -> None:
        with self.lock:
            drive = self.drives[node]
            drive.powered = True
            drive._boot()

    def bus_error(self, state: str = "error-passive") -> None:
        """What the host's CAN controller would report: an error frame (SocketCAN convention)."""
        if state == "bus-off":
            msg = can.Message(arbitration_id=p.CAN_ERR_BUSOFF, is_error_frame=True, data=bytes(8))
        else:
            msg = can.Message(arbitration_id=p.CAN_ERR_CRTL, is_error_frame=True,
                              data=bytes((0, p.CAN_ERR_CRTL_RX_PASSIVE, 0, 0, 0, 0, 0, 0)))
        self.network.bus.send(msg)

    # -- socketcand ------------------------------------------------------------------------------
    def serve_socketcand(self, host: str = "127.0.0.1", port: int = 0) -> tuple[str, int]:
        """Serve this bus to other processes over the socketcand protocol."""
        from robots.canopen.socketcand import SocketcandServer
        server = SocketcandServer(self.channel, host, port)
        server.start()
        self._servers.append(server)
        return server.address

    serve_tcp = serve_socketcand         # the name `interbot emulate` calls

    def close(self) -> None:
        self._stop.set()
        if self.lockstep is not None and self.lockstep.pump == self._pump:
            self.lockstep.pump = None
        if self._thread is not None:
            self._thread.join(timeout=1.0)
        for server in self._servers:
            server.close()
        self._servers.clear()
        try:
            self.network.disconnect()
        except Exception:
            pass
