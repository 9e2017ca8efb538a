"""What every streaming sensor driver shares: the port, the reader thread, liveness, reconnecting.

Why: a laser on a serial line or a socket fails in the same few ways whatever its protocol. It
falls silent, it sends bytes that form no telegram (wrong baud rate, a loose RS-422 pair), or
its port goes away (the USB adapter is pulled). Each must become a *link fault* that the rest of
the robot can see (`link_up`, `link_error`), never a stale reading passed on as if fresh; and
once the device is back the driver must find it again by itself, with back-off, going through
the whole handshake (the device may have been power-cycled meanwhile).

On a simulated clock, with an in-process emulator (`lockstep` given), there is no reader
thread: `poll()`, called by the tick loop right after the world stepped, reads every byte the
emulator wrote, and liveness runs on the simulated clock, so a `--fast` run stays
deterministic (as for the P2OS driver). There the driver does not reconnect.

`StreamingSensor` is that plumbing. A protocol's driver subclasses it and supplies
`_handshake(port)` (configure the device and start its stream; raise `LinkError` when it does
not answer), `_feed(data)` (decode bytes; call `_fresh()` for every good reading) and, where it
can, `_garbage()` (what its parser threw away, for the fault's reason) and `_goodbye(port)`
(stop the stream on close).
"""
from __future__ import annotations

import logging
import threading
import time

import numpy as np
import serial

from robots.devices import LaserScan
from robots.exceptions import LinkError
from robots.link.arrival import read_arrived
from robots.link.backoff import Backoff
from robots.link.lockstep import LockStep
from robots.link.port import open_serial

log = logging.getLogger(__name__)

READ_QUANTUM = 0.02        # s, longest a read blocks (so close() and liveness stay prompt)
FLOOD_KEEP = 1 << 16       # bytes of one read decoded at most (~20 scans of a 1081-step laser): the
                           # newest of a flood, so a reading's age is the age of its arrival


class SensorPort:
    """A pyserial port (a device, a pty path or socket://host:port) with timed reads."""

    def __init__(self, url: str, baud: int, write_timeout: float = 1.0,
                 lockstep: LockStep | None = None) -> None:
        self.serial = open_serial(url, "the port", baudrate=baud, timeout=READ_QUANTUM,
                                  write_timeout=write_timeout)
        self.url = url
        self.lockstep = lockstep
        # a raw socket (socket://, e.g. a serial-to-Ethernet converter) has no line speed to set
        self.has_line_speed = not url.startswith("socket://")

    @property
    def baud(self) -> int:
        return self.serial.baudrate

    def set_baud(self, baud: int) -> None:
        """Change the line speed (a no-op on a socket)."""
        self.serial.baudrate = baud

    def write(self, data: bytes) -> None:
        """Write; in lock-step, return once the emulator has acted on it."""
        if self.lockstep is not None:
            self.lockstep.to_device.wrote(len(data))
        self.serial.write(data)
        if self.lockstep is not None:
            self.lockstep.deliver(2.0)

    def read(self, timeout: float) -> bytes:
        """What is there, or wait up to `timeout` s for at least one byte."""
        data = self._read(timeout)
        if data and self.lockstep is not None:
            self.lockstep.to_host.got(len(data))
        return data

    def _read(self, timeout: float) -> bytes:
        """All that has arrived, on a tty, a pty or a socket (robots.link.arrival)."""
        return read_arrived(self.serial, timeout)

    def discard_input(self) -> None:
        self.serial.reset_input_buffer()

    def close(self) -> None:
        try:
            self.serial.close()
        except Exception:
            pass


class StreamingSensor:
    """A sensor that streams readings over a port; see the module docstring."""

    name = "sensor"

    def __init__(self, url: str, baud: int, clock=None, stale_after: float = 0.5,
                 reconnect: bool = True, lockstep: LockStep | None = None) -> None:
        if stale_after <= 0:
            raise ValueError(f"stale_after must be > 0 s, got {stale_after}")
        self.url = url
        self.baud = int(baud)
        self.clock = clock
        self.stale_after = float(stale_after)
        self.reconnect = reconnect and lockstep is None
        self.lockstep = lockstep
        self.emulator = None                  # an in-process emulator this driver closes
        self.backoff = Backoff(initial=0.1, factor=2.0, maximum=2.0)
        self.stats = {"readings": 0, "link_downs": 0, "reconnects": 0}
        self.link_error = ""                  # why the link is down ("" while up)
        self.last_error = ""                  # the newest problem, kept after recovery
        self._port: SensorPort | None = None
        self._link_up = False
        self._lock = threading.RLock()
        self._fresh_cond = threading.Condition()
        self._closing = threading.Event()
        self._reader: threading.Thread | None = None
        self._last_fresh = -float("inf")      # monotonic time of the newest good reading
        self._arrived: float | None = None    # when the bytes being decoded were read
        self._connected_at = -float("inf")    # ... and of the newest (re)connection
        self._next_attempt = 0.0

    # -- what a protocol supplies ---------------------------------------------------------------
    def _handshake(self, port: SensorPort) -> None:
        """Configure the device and start its stream (raise LinkError if it does not answer)."""
        raise NotImplementedError

    def _feed(self, data: bytes) -> None:
        """Decode bytes from the device; call `_fresh()` for each good reading."""
        raise NotImplementedError

    def _garbage(self) -> str:
        """What the parser threw away, for a fault's reason ("" when nothing)."""
        return ""

    def _goodbye(self, port: SensorPort) -> None:
        """Stop the device's stream before the port closes (best effort)."""

    def _reset_decoder(self) -> None:
        """Forget half-decoded bytes (a new connection)."""

    # -- time -----------------------------------------------------------------------------------
    def now(self) -> float:
        """Robot time for reading stamps (the clock the hardware was opened with)."""
        return self.clock.now() if self.clock is not None else time.monotonic()

    def _time(self) -> float:
        """Time for liveness: the simulated clock in lock-step, else monotonic."""
        return self.clock.now() if self.lockstep is not None else time.monotonic()

    # -- life cycle -------------------------------------------------------------------------------
    def open(self) -> None:
        """Connect (handshake) and start the reader thread. Raises LinkError/HandshakeError."""
        self._closing.clear()
        self._connect()
        if self.lockstep is not None:
            return                                # poll() reads, on the tick thread
        self._reader = threading.Thread(target=self._read_loop, name=f"{self.name}-reader",
                                        daemon=True)
        self._reader.start()

    def close(self) -> None:
        self._closing.set()
        if self._reader is not None and self._reader is not threading.current_thread():
            self._reader.join(timeout=2.0)
        self._reader = None
        with self._lock:
            port = self._port
            if port is not None and self._link_up:
                try:
                    self._goodbye(port)
                except Exception:
                    pass
            self._drop_port()
            self._link_up = False
            self.link_error = "closed"
        if self.emulator is not None:
            self.emulator.close()
            self.emulator = None

    def poll(self) -> None:
        """Lock-step: decode everything the emulator wrote; check liveness in sim time."""
        if self.lockstep is None or not self._link_up:
            return
        deadline = time.monotonic() + 2.0
        while self._port is not None and self.lockstep.to_host.backlog() > 0:
            if time.monotonic() > deadline:
                self.last_error = f"{self.url}: emulator bytes did not arrive in time"
                break
            self._read_once()
        self._check_liveness()

    @property
    def link_up(self) -> bool:
        return self._link_up

    def fresh(self) -> bool:
        """Whether the link is up and the newest reading is younger than `stale_after` (a
        reading from before a fault never counts, even right after reconnecting)."""
        return self._link_up and self._time() - self._last_fresh <= self.stale_after

    def wait_for_reading(self, after: int, timeout: float) -> bool:
        """Block until more than `after` readings were decoded (tests and tools)."""
        with self._fresh_cond:
            return self._fresh_cond.wait_for(lambda: self.stats["readings"] > after, timeout)

    # -- connecting -------------------------------------------------------------------------------
    def _connect(self) -> None:
        self._drop_port()
        port = SensorPort(self.url, self.baud, lockstep=self.lockstep)
        if self.lockstep is not None:
            self.lockstep.reset()
        try:
            self._reset_decoder()
            self._handshake(port)
        except (serial.SerialException, OSError) as exc:
            port.close()
            raise LinkError(f"{self.url}: link failed during the handshake: {exc}") from exc
        except BaseException:
            port.close()
            raise
        with self._lock:
            if self._closing.is_set():            # close() came during the handshake
                port.close()
                raise LinkError(f"{self.url}: closed during the handshake")
            self._port = port
            self._reset_decoder()
            self._connected_at = self._time()   # the stream gets its full grace to start
            self._link_up = True
            self.link_error = ""
        log.info("%s: %s connected", self.url, self.name)

    # -- the reader thread ------------------------------------------------------------------------
    def _read_loop(self) -> None:
        while not self._closing.is_set():
            if not self._link_up:
                if not self.reconnect:
                    self._closing.wait(0.1)
                    continue
                self._reconnect_with_backoff()
                continue
            try:
                self._read_once()
                self._check_liveness()
            except Exception as exc:             # never let the reader die with the link "up"
                log.debug("%s: reader failed", self.url, exc_info=True)
                self._link_lost(f"reader error: {type(exc).__name__}: {exc}")

    def _read_once(self) -> None:
        port = self._port
        if port is None:
            return
        try:
            data = port.read(READ_QUANTUM)
        except (serial.SerialException, OSError, TypeError, AttributeError) as exc:
            self._link_lost(f"port error (unplugged?): {exc}")
            return
        if not data:
            return
        self._arrived = self._time()
        parser = getattr(self, "parser", None)
        if self.lockstep is None and hasattr(parser, "skip_older"):
            data = parser.skip_older(data, FLOOD_KEEP)
        try:
            self._feed(data)
        finally:
            self._arrived = None

    def _fresh(self) -> None:
        """A protocol decoded one good reading (stamped with when its bytes were read)."""
        self._last_fresh = self._arrived if self._arrived is not None else self._time()
        with self._fresh_cond:
            self.stats["readings"] += 1
            self._fresh_cond.notify_all()

    def _check_liveness(self) -> None:
        silent = self._time() - max(self._last_fresh, self._connected_at)
        if self._link_up and silent > self.stale_after:
            garbage = self._garbage()
            why = f"no reading for {silent:.2f} s (allowed {self.stale_after:.2f} s)"
            self._link_lost(f"{why}; {garbage}" if garbage else f"{why}; the device is silent")

    def _link_lost(self, why: str) -> None:
        with self._lock:
            if not self._link_up:
                return
            self._link_up = False
            self._last_fresh = -float("inf")      # nothing from before the fault is passed on
            self.link_error = why
            self.last_error = f"{self.url}: link down: {why}"
            self.stats["link_downs"] += 1
            log.warning("%s", self.last_error)
            self._drop_port()
            self._next_attempt = time.monotonic() + self.backoff.next_delay()

    def _reconnect_with_backoff(self) -> None:
        delay = max(0.0, self._next_attempt - time.monotonic())
        if self._closing.wait(delay):
            return
        try:
            self._connect()
        except LinkError as exc:
            self.last_error = str(exc)
            self.link_error = f"reconnecting: {exc}"
            self._next_attempt = time.monotonic() + self.backoff.next_delay()
            return
        self.backoff.reset()
        self.stats["reconnects"] += 1
        log.info("%s: %s is back", self.url, self.name)

    def _drop_port(self) -> None:
        port, self._port = self._port, None
        if port is not None:
            port.close()


class ScanningSensor(StreamingSensor):
    """A streaming range sensor (a laser): the newest good scan, bad scans dropped and
    counted, and what the parser threw away since the newest good one. A driver sets `parser`
    (with `stats`), `angles`, `mount` and `max_range`, and calls `_publish` or `_bad_scan`."""

    def _start_scans(self, mount, max_range: float | None) -> None:
        self.mount = tuple(float(v) for v in mount)
        self.max_range = max_range
        self.stats.update(bad_scans=0)
        self._scan: LaserScan | None = None
        self._bytes_mark = 0                 # parser's bytes in at the newest good scan

    def read(self) -> LaserScan | None:
        """The newest scan while the link is up and fresh; None otherwise (never a stale one)."""
        return self._scan if self.fresh() else None

    def _publish(self, ranges: np.ndarray) -> None:
        """A good scan (ranges in m, inf without an echo), cut at max_range."""
        if self.max_range is not None:
            ranges[ranges > self.max_range] = np.inf
        self._scan = LaserScan(t=self.now(), angles=self.angles, ranges=ranges,
                               origin=self.mount)
        self._bytes_mark = self.parser.stats.bytes_in
        self._fresh()

    def _bad_scan(self, why: str) -> None:
        self.stats["bad_scans"] += 1
        self.last_error = f"{self.url}: dropped a scan: {why}"

    def _reset_decoder(self) -> None:
        self.parser.reset()
        self._bytes_mark = self.parser.stats.bytes_in

    def _garbage_since_scan(self, unit: str) -> str:
        """The bytes since the newest good scan that formed no `unit`, and the last cause."""
        stats = self.parser.stats
        dropped = stats.bytes_in - self._bytes_mark     # dropped, or held in an unfinished frame
        if dropped <= 0:
            return ""
        last = f"; last: {stats.last_error}" if stats.last_error else ""
        return f"{dropped} bytes formed no {unit}{last}"
