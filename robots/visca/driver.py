"""The VISCA pan-tilt head driver: a Sony EVI-D31/D70 (or the emulator) behind any pyserial URL.

`ViscaHead(spec, url)` opens `/dev/ttyUSB1`, `socket://host:port` or a pty path and is a
`PanTiltHead`: `point(pan, tilt)` sets a goal (clamped to the profile's [head] limits), `read()`
gives the newest position the camera reported. `open()` runs the VISCA start-up (AddressSet and
IF_Clear, both broadcast, then CAM_VersionInq and a first position inquiry), then a worker
thread owns the line: it sends a new goal as an AbsolutePosition at the profile's rated speed
(cancelling the motion still running first: the camera runs one pan-tilt motion at a time) and
asks for the position every PERIOD s.

Faults (the P2OS driver's rules): no valid reply for SILENCE s (a silent camera, or one that
sends only garbage), or MAX_ERRORS error replies in a row, takes the link down. On the way
out it sends Cancel and Pan-tiltDrive Stop (the line may still carry them), forgets the goal
(nothing resumes by itself), says why in `fault()` and the log, and reconnects with back-off;
a new `point()` moves the head again. Counters in `stats`.

In the simulated world (`for_simulation`) the driver talks to the camera emulator on a pty, as
the base's driver talks to its firmware emulator. On a simulated clock it has no thread: a new
goal is sent within `point()` and the position asked for in `poll()` (once a tick, after the
world stepped), so a `--fast` run stays deterministic; there it does not reconnect (the
emulator lives in the same process: a dead link is a broken run).
"""
from __future__ import annotations

import logging
import math
import threading
import time

import serial

from robots.devices import PanTiltHead
from robots.exceptions import HandshakeError, LinkError, ProtocolError
from robots.link.backoff import Backoff
from robots.link.port import open_serial
from robots.profile import HeadSpec
from robots.visca import protocol as p

log = logging.getLogger(__name__)

PERIOD = 0.05            # s between position inquiries
REPLY_TIMEOUT = 0.3      # s to wait for one reply
SILENCE = 0.6            # s without a valid reply -> link down
WRITE_TIMEOUT = 1.0      # s a write may block
# In lock-step with the simulated world the emulator answers every command before the world
# steps, so the real-time limits only guard against a deadlock: a machine loaded with other
# work must not look like a dead link (robot time stands still while the answer is awaited).
LOCKSTEP_LIMITS = {"reply_timeout": 5.0, "silence": 10.0, "write_timeout": 5.0}
MAX_ERRORS = 3           # error replies in a row -> link down
DEADBAND_DEG = 0.5       # a goal closer than this to the one sent is not sent again
READ_QUANTUM = 0.02      # s, longest a read blocks


class ViscaHead(PanTiltHead):
    """A VISCA pan-tilt head. Options: model ("evi-d31", "evi-d70"; the camera's own answer to
    CAM_VersionInq wins), address (1..7), baud, reply_timeout, period, silence, max_errors,
    reconnect."""

    def __init__(self, spec: HeadSpec, url: str, *, model: str = "evi-d31", address: int = 1,
                 baud: int = 9600, reply_timeout: float = REPLY_TIMEOUT, period: float = PERIOD,
                 silence: float = SILENCE, max_errors: int = MAX_ERRORS, reconnect: bool = True,
                 clock=None, write_timeout: float = WRITE_TIMEOUT) -> None:
        self.spec = spec
        self.url = url
        self.model = p.model_named(model)
        self.address = int(address)
        self.baud = int(baud)
        self.reply_timeout = float(reply_timeout)
        self.period = float(period)
        self.silence = float(silence)
        self.write_timeout = float(write_timeout)
        self.max_errors = int(max_errors)
        self.reconnect = bool(reconnect)
        self.clock = clock
        self.simulated = bool(getattr(clock, "simulated", False))
        self.emulator = None                            # set by for_simulation
        self.backoff = Backoff(initial=0.1, factor=2.0, maximum=2.0)
        self.parser = p.ViscaParser(gap_timeout=0.1)
        self.stats = {"replies": 0, "timeouts": 0, "errors": 0, "bad_replies": 0, "commands": 0,
                      "cancels": 0, "clears": 0, "link_downs": 0, "reconnects": 0}
        self.last_error = ""
        self._port: serial.SerialBase | None = None
        self._lock = threading.RLock()
        self._wake = threading.Event()
        self._closing = threading.Event()
        self._worker: threading.Thread | None = None
        self._link_up = False
        self._goal: tuple[int, int] | None = None       # units, asked for by point()
        self._sent: tuple[int, int] | None = None       # units, accepted by the camera
        self._socket = 0                                # the socket our motion holds
        self._position = (0.0, 0.0)                     # rad, newest reported
        self._last_reply = -math.inf
        self._errors_in_row = {"command": 0, "inquiry": 0}   # refusals since the last success
        self._next_attempt = 0.0

    @classmethod
    def for_profile(cls, profile, url: str, clock=None, **options) -> "ViscaHead":
        """A head at `url` shaped by the profile's [head] (limits, rated speed, model)."""
        if profile.head is None:
            raise LinkError(f"robot '{profile.name}' has no [head] in its profile")
        options.setdefault("model", getattr(profile.head, "model", "") or "evi-d31")
        return cls(profile.head, url, clock=clock, **options)

    @classmethod
    def for_simulation(cls, profile, simulation, clock) -> "ViscaHead":
        """The camera emulator on a pty, stepped with `simulation`; a driver for that pty."""
        from robots.visca.emulator import ViscaEmulator    # the emulator only when simulating
        emulator = ViscaEmulator.for_profile(profile, simulation.world)   # the world's head
        emulator.attach(simulation)
        lockstep = getattr(clock, "simulated", False)
        head = cls.for_profile(profile, emulator.serve_pty(), clock=clock, reconnect=not lockstep,
                               **(LOCKSTEP_LIMITS if lockstep else {}))
        head.emulator = emulator
        return head

    # -- PanTiltHead -----------------------------------------------------------------------------
    def open(self) -> None:
        self._closing.clear()
        self._connect()
        if self.simulated:
            return
        self._worker = threading.Thread(target=self._run, name="visca-head", daemon=True)
        self._worker.start()

    def poll(self) -> None:
        """Simulated clock: ask where the head is now, and check the link (once a tick)."""
        if not self.simulated or not self._link_up:
            return
        try:
            self._inquire_position()
        except (serial.SerialException, OSError) as exc:
            self._link_lost(f"port error: {exc}")
            return
        if time.monotonic() - self._last_reply > self.silence:
            self._link_lost(f"no valid reply for {time.monotonic() - self._last_reply:.2f} s"
                            + self._garbage_note())

    def point(self, pan: float, tilt: float) -> None:
        """Aim at (pan, tilt) rad, clamped to the profile's limits; NaN keeps that axis's goal."""
        with self._lock:
            old = self._goal_radians()
            pan = _clamp(pan, self.spec.pan_min, self.spec.pan_max, old[0])
            tilt = _clamp(tilt, self.spec.tilt_min, self.spec.tilt_max, old[1])
            self._goal = p.units_of(self.model, pan, tilt)
        if self.simulated:
            self._send_now()
        else:
            self._wake.set()

    def read(self) -> tuple[float, float]:
        return self._position

    def fault(self) -> str | None:
        return None if self._link_up else (self.last_error or f"{self.url}: head not connected")

    def stop(self) -> None:
        """Stop where the head is (the worker cancels the running motion)."""
        with self._lock:
            self._goal = None
        if self.simulated:
            self._send_now()
        else:
            self._wake.set()

    def close(self) -> None:
        self._closing.set()
        self._wake.set()
        if self._worker is not None and self._worker is not threading.current_thread():
            self._worker.join(timeout=2.0)
        self._worker = None
        with self._lock:
            if self._port is not None and self._link_up:
                self._stop_on_the_way_out()
            self._drop_port()
            self._link_up = False
        if self.emulator is not None:
            self.emulator.close()
            self.emulator = None

    @property
    def link_up(self) -> bool:
        return self._link_up

    # -- start-up -------------------------------------------------------------------------------
    def _connect(self) -> None:
        """Open the port; AddressSet, IF_Clear, CAM_VersionInq, a position. Raises LinkError."""
        self._drop_port()
        self._port = open_serial(self.url, "the head's port", baudrate=self.baud,
                                 timeout=READ_QUANTUM, write_timeout=self.write_timeout)
        self.parser.reset()
        try:
            self._start_up()
        except (serial.SerialException, OSError) as exc:
            self._drop_port()
            raise LinkError(f"{self.url}: head link failed during start-up: {exc}") from exc
        except Exception:
            self._drop_port()
            raise
        with self._lock:
            self._goal = self._sent = None          # nothing resumes by itself
            self._socket = 0
            self._errors_in_row = {"command": 0, "inquiry": 0}
            self._link_up = True
        log.info("%s: VISCA %s at address %d", self.url, self.model.name, self.address)

    def _start_up(self) -> None:
        steps = ((p.address_set(), lambda r: r.kind == "address_set", "AddressSet (88 30 01 FF)"),
                 (p.if_clear(), lambda r: r.kind == "if_clear", "IF_Clear (88 01 00 01 FF)"))
        for packet, wanted, name in steps:
            if self._exchange(packet, wanted) is None:
                raise HandshakeError(f"{self.url}: no answer to {name} within "
                                     f"{self.reply_timeout:g} s; is a VISCA camera on this port, "
                                     f"powered, at {self.baud} baud?")
        version = self._exchange(p.version_inquiry(self.address), _answer_or_error)
        if version is not None and version.kind == "answer":
            self._adopt_model(version)
        if not self._inquire_position():
            raise HandshakeError(f"{self.url}: the camera at address {self.address} does not "
                                 f"answer Pan-tiltPosInq (8{self.address} 09 06 12 FF)")

    def _adopt_model(self, reply: p.Reply) -> None:
        try:
            _, model_id, _, _ = p.decode_version(reply)
        except ProtocolError as exc:
            log.warning("%s: bad CAM_VersionInq answer: %s", self.url, exc)
            return
        known = {m.model_id: m for m in p.MODELS.values()}
        if model_id in known and known[model_id] is not self.model:
            log.info("%s: the camera says it is an %s (profile: %s)", self.url,
                     known[model_id].name, self.model.name)
            self.model = known[model_id]

    # -- the worker ------------------------------------------------------------------------------
    def _run(self) -> None:
        while not self._closing.is_set():
            if not self._link_up:
                self._reconnect_with_backoff()
                continue
            try:
                self._cycle()
            except (serial.SerialException, OSError, TypeError, AttributeError) as exc:
                self._link_lost(f"port error: {exc}")
                continue
            if time.monotonic() - self._last_reply > self.silence:
                self._link_lost(f"no valid reply for {time.monotonic() - self._last_reply:.2f} s"
                                + self._garbage_note())
                continue
            self._wake.wait(self.period)
            self._wake.clear()

    def _cycle(self) -> None:
        """Send a new goal (or stop), then ask where the head is."""
        self._send_pending()
        self._inquire_position()

    def _send_pending(self) -> None:
        """Cancel the running motion for no goal; send a goal that moved enough."""
        with self._lock:
            goal = self._goal
        if goal is None and self._socket:
            self._cancel()
        elif goal is not None and self._worth_sending(goal):
            if self._socket:
                self._cancel()
            self._send_goal(goal)

    def _send_now(self) -> None:
        """Simulated clock: send what `point`/`stop` changed at once (no worker thread)."""
        if not self._link_up:
            return
        try:
            self._send_pending()
        except (serial.SerialException, OSError) as exc:
            self._link_lost(f"port error: {exc}")

    def _worth_sending(self, goal: tuple[int, int]) -> bool:
        if self._sent is None:
            return True
        pan_band = DEADBAND_DEG * self.model.pan_units_per_deg
        tilt_band = DEADBAND_DEG * self.model.tilt_units_per_deg
        moved = abs(goal[0] - self._sent[0]) >= pan_band or abs(goal[1] - self._sent[1]) >= tilt_band
        return moved or (not self._socket and goal != self._sent)

    def _send_goal(self, goal: tuple[int, int]) -> None:
        rate = math.degrees(self.spec.max_pan_rate)
        packet = p.absolute_position(self.address, p.speed_code(self.model.pan_deg_s, rate),
                                     p.speed_code(self.model.tilt_deg_s, rate), *goal,
                                     model=self.model)
        self.stats["commands"] += 1
        reply = self._exchange(packet, _ack_or_error)
        if reply is None:
            return
        if reply.kind == "ack":
            self._socket, self._sent = reply.socket, goal
            self._errors_in_row["command"] = 0
        else:
            self._on_error(reply, "AbsolutePosition", "command")

    def _cancel(self) -> None:
        self.stats["cancels"] += 1
        socket, self._socket = self._socket, 0
        self._exchange(p.cancel(self.address, socket), _error_reply)   # cancelled or no socket
        self._sent = None

    def _inquire_position(self) -> bool:
        reply = self._exchange(p.position_inquiry(self.address), _answer_or_error)
        if reply is None:
            return False
        if reply.kind == "error":
            self._on_error(reply, "Pan-tiltPosInq", "inquiry")
            return False
        try:
            pan, tilt = p.decode_position(reply)
        except ProtocolError as exc:
            self.stats["bad_replies"] += 1
            self.last_error = f"{self.url}: {exc}"
            return False
        self._position = p.radians_of(self.model, pan, tilt)
        self._errors_in_row["inquiry"] = 0
        return True

    def _on_error(self, reply: p.Reply, what: str, kind: str) -> None:
        """An error reply: count it; clear the camera's sockets when it is busy. MAX_ERRORS
        refused commands (or inquiries) in a row, whatever else succeeds meanwhile, take the
        link down: a head that answers but will not move cannot be driven."""
        self.stats["errors"] += 1
        self._errors_in_row[kind] += 1
        self.last_error = f"{self.url}: {what} refused: {reply.error_name}"
        log.debug("%s", self.last_error)
        if reply.code in (p.ErrorCode.BUFFER_FULL, p.ErrorCode.NOT_EXECUTABLE):
            self.stats["clears"] += 1
            self._exchange(p.if_clear(self.address), lambda r: r.kind == "completion")
            self._socket, self._sent = 0, None
        if self._errors_in_row[kind] >= self.max_errors:
            self._link_lost(f"{self._errors_in_row[kind]} error replies in a row, the last to "
                            f"{what}: {reply.error_name}")

    # -- the line -------------------------------------------------------------------------------
    def _exchange(self, packet: bytes, wanted) -> p.Reply | None:
        """Send `packet`; the first reply `wanted` accepts, or None after REPLY_TIMEOUT s.
        Completions and other replies on the way are handled as they come."""
        port = self._port
        if port is None:
            return None
        port.write(packet)
        deadline = time.monotonic() + self.reply_timeout
        while time.monotonic() < deadline:
            data = port.read(max(1, port.in_waiting))
            if not data:
                continue
            for frame in self.parser.feed(data, time.monotonic()):
                reply = self._decode(frame)
                if reply is None:
                    continue
                if wanted(reply):
                    return reply
                self._unsolicited(reply)
        self.stats["timeouts"] += 1
        return None

    def _decode(self, frame: bytes) -> p.Reply | None:
        try:
            reply = p.decode_reply(frame)
        except ProtocolError as exc:
            self.stats["bad_replies"] += 1
            self.last_error = f"{self.url}: bad reply {frame.hex(' ')}: {exc}"
            return None
        if reply.kind not in ("address_set", "if_clear") and reply.address != self.address:
            self.stats["bad_replies"] += 1
            return None
        self.stats["replies"] += 1
        self._last_reply = time.monotonic()
        return reply

    def _unsolicited(self, reply: p.Reply) -> None:
        """A completion frees our socket; the rest is only counted."""
        if reply.kind == "completion" and reply.socket and reply.socket == self._socket:
            self._socket = 0
        elif reply.kind == "error":
            self.stats["errors"] += 1

    def _garbage_note(self) -> str:
        stats = self.parser.stats
        if not stats.dropped_bytes and not self.stats["bad_replies"]:
            return ""
        return (f" ({stats.dropped_bytes} bytes formed no packet, {self.stats['bad_replies']} "
                f"packets were no valid reply; last: {stats.last_error or self.last_error})")

    # -- faults ---------------------------------------------------------------------------------
    def _link_lost(self, why: str) -> None:
        with self._lock:
            if not self._link_up:
                return
            self.last_error = f"{self.url}: head link down: {why}"
            log.warning("%s", self.last_error)
            self.stats["link_downs"] += 1
            self._stop_on_the_way_out()
            self._drop_port()
            self._link_up = False
            self._goal = self._sent = None
            self._socket = 0
            self._next_attempt = time.monotonic() + self.backoff.next_delay()

    def _stop_on_the_way_out(self) -> None:
        """Cancel and Stop, without waiting: a camera still listening stops where it is."""
        port = self._port
        if port is None:
            return
        top_pan, top_tilt = self.model.max_pan_speed, self.model.max_tilt_speed
        packets = [p.cancel(self.address, s) for s in ([self._socket] if self._socket else [])]
        packets.append(p.pan_tilt_drive(self.address, p.Direction.STOP, top_pan, top_tilt,
                                        self.model))
        try:
            port.write(b"".join(packets))
        except Exception:
            pass                          # the line is gone: nothing to stop through

    def _reconnect_with_backoff(self) -> None:
        if not self.reconnect:
            self._closing.wait(0.1)
            return
        if self._closing.wait(max(0.0, self._next_attempt - time.monotonic())):
            return
        try:
            self._connect()
        except LinkError as exc:
            self.last_error = str(exc)
            self._next_attempt = time.monotonic() + self.backoff.next_delay()
            return
        self.backoff.reset()
        self.stats["reconnects"] += 1
        log.info("%s: head link back", self.url)

    def _drop_port(self) -> None:
        port, self._port = self._port, None
        if port is not None:
            try:
                port.close()
            except Exception:
                pass

    def _goal_radians(self) -> tuple[float, float]:
        if self._goal is None:
            return self._position
        return p.radians_of(self.model, *self._goal)


def _ack_or_error(reply: p.Reply) -> bool:
    return reply.kind in ("ack", "error")


def _answer_or_error(reply: p.Reply) -> bool:
    return reply.kind == "answer" or (reply.kind == "error" and reply.socket == 0)


def _error_reply(reply: p.Reply) -> bool:
    return reply.kind == "error"


def _clamp(value: float, low: float, high: float, fallback: float) -> float:
    """`value` within [low, high]; NaN or infinity keeps the previous goal (no jump)."""
    value = float(value)
    if not math.isfinite(value):
        return fallback
    return min(high, max(low, value))
