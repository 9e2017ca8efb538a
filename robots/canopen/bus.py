"""Opening a CAN bus from a `--port` string, and the wrapper that counts and logs what we send.

Port syntax: `INTERFACE:CHANNEL`, python-can's names, e.g. `socketcan:can0`,
`pcan:PCAN_USBBUS1`, `virtual:NAME`; `socketcand:HOST:PORT` (channel can0) or
`socketcand:HOST:PORT:CHANNEL` for a socketcand server such as `interbot emulate can`.
A `?log=FILE` suffix writes a candump `-l` log of the session.

Why a wrapper: on a simulated clock the driver and the in-process emulator run in lock-step
(`robots.link.LockStep`, counting frames instead of bytes): every frame the driver sends is
acted on by the emulator before `send` returns. The same wrapper tees every frame sent into
the session log (python-can buses do not see their own frames).

Why `LockStepReceiver`: in lock-step on the in-process bus the emulator's answers are already
queued on our bus when `send` returns, so the driver reads them itself, on its own thread,
instead of a Notifier thread that each frame would have to wake (a hand-over per frame, and a
wait for the interpreter lock, about a dozen a tick).
"""
from __future__ import annotations

import logging
import queue
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import can

from robots.canopen.virtual_send import virtual_sender
from robots.exceptions import LinkError
from robots.link.lockstep import ByteCounter

NO_BITRATE = {"virtual", "socketcan", "socketcand"}     # interfaces that take no bitrate argument


@dataclass(frozen=True)
class PortSpec:
    interface: str
    channel: str
    kwargs: dict = field(default_factory=dict)
    log: str | None = None

    def __str__(self) -> str:
        return f"{self.interface}:{self.channel}"


def parse_port(port: str) -> PortSpec:
    """`INTERFACE:CHANNEL[?log=FILE]` -> PortSpec; the error shows the syntax."""
    text, _, query = port.partition("?")
    log = None
    if query:
        key, _, value = query.partition("=")
        if key != "log" or not value:
            raise LinkError(f"CAN port {port!r}: unknown option {query!r}; the only one is ?log=FILE")
        log = value
    interface, sep, rest = text.partition(":")
    if not sep or not interface or not rest:
        raise LinkError(f"CAN port {port!r}: expected INTERFACE:CHANNEL, e.g. socketcan:can0, "
                        f"pcan:PCAN_USBBUS1, virtual:NAME or socketcand:127.0.0.1:29536")
    if interface == "socketcand":
        parts = rest.split(":")
        if len(parts) not in (2, 3) or not parts[1].isdigit():
            raise LinkError(f"CAN port {port!r}: socketcand needs HOST:PORT[:CHANNEL], "
                            f"e.g. socketcand:127.0.0.1:29536")
        channel = parts[2] if len(parts) == 3 else "can0"
        return PortSpec(interface, channel, {"host": parts[0], "port": int(parts[1])}, log)
    if interface not in can.VALID_INTERFACES:
        raise LinkError(f"CAN port {port!r}: unknown python-can interface {interface!r}; known: "
                        f"{', '.join(sorted(can.VALID_INTERFACES))}")
    return PortSpec(interface, rest, {}, log)


def open_bus(spec: PortSpec, bitrate: int | None = None) -> can.BusABC:
    kwargs = dict(spec.kwargs)
    if bitrate and spec.interface not in NO_BITRATE:
        kwargs["bitrate"] = bitrate
    try:
        return can.Bus(interface=spec.interface, channel=spec.channel, **kwargs)
    except Exception as exc:          # python-can raises many kinds (CanError, OSError, ImportError)
        raise LinkError(f"CAN port {spec}: cannot open the interface: {exc} (is the adapter "
                        f"plugged in and the interface up, e.g. `ip link set can0 up type can "
                        f"bitrate {bitrate or 500000}`?)") from exc


class CandumpLog:
    """A session log in candump `-l` format: `(seconds.micros) CHANNEL ID#DATA`, one frame a line."""

    def __init__(self, path: str | Path, channel: str = "can0") -> None:
        self.path = Path(path)
        self.channel = channel
        self._file = open(self.path, "w", encoding="ascii")
        self._lock = threading.Lock()
        self.frames = 0

    def write(self, msg: can.Message) -> None:
        stamp = msg.timestamp or time.time()
        width = 8 if msg.is_extended_id else 3
        if msg.is_error_frame:
            ident, payload = f"{0x20000000 | msg.arbitration_id:08X}", msg.data.hex().upper()
        else:
            ident = f"{msg.arbitration_id:0{width}X}"
            payload = "R" if msg.is_remote_frame else bytes(msg.data).hex().upper()
        with self._lock:
            if self._file.closed:
                return
            self._file.write(f"({stamp:.6f}) {self.channel} {ident}#{payload}\n")
            self.frames += 1

    def on_message_received(self, msg: can.Message) -> None:   # a python-can listener, too
        self.write(msg)

    def close(self) -> None:
        with self._lock:
            self._file.close()


class DriverBus:
    """A bus that counts sent frames for lock-step and tees them into the log. The driver's
    `send` also waits until the emulator has handled the frame (`wait`), through `deliver`
    (`LockStep.deliver`: the in-process emulator reads it on this thread); the emulator's not."""

    def __init__(self, bus: can.BusABC, counter: ByteCounter | None = None,
                 log: CandumpLog | None = None, drain_timeout: float = 2.0, wait: bool = True,
                 deliver: Callable[[float], bool] | None = None) -> None:
        self.bus = bus
        # lock-step on the in-process bus: reads the frames waiting here (LockStepReceiver)
        self.receive: Callable[[], None] | None = None
        self.counter = counter
        self.wait = wait
        self.deliver = deliver or (counter.wait_drained if counter is not None else None)
        self._send = virtual_sender(bus)      # python-can's own send but without its deepcopy
        self.log = log
        self.drain_timeout = drain_timeout
        self.channel_info = getattr(bus, "channel_info", "can")
        self.sent = 0
        self.lost: Exception | None = None     # set when receiving found the link gone
        self._queue = _virtual_queue(bus)

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        if self.receive is not None:
            self.receive()                    # the frames sent before ours first: in bus order
        if self.counter is not None:
            self.counter.wrote(1)
        try:
            self._send(msg, timeout)
        except OSError as exc:                # a socketcand/TCP link gone: a CAN link fault,
            if self.counter is not None:      # never a BrokenPipeError taken for our stdout
                self.counter.got(1)
            raise can.CanOperationError(f"CAN link lost ({type(exc).__name__}: {exc})") from exc
        except Exception:
            if self.counter is not None:
                self.counter.got(1)           # never arrives: do not wait for it
            raise
        self.sent += 1
        if self.log is not None:
            self.log.write(can.Message(timestamp=time.time(), arbitration_id=msg.arbitration_id,
                                       data=msg.data, is_extended_id=msg.is_extended_id,
                                       is_remote_frame=msg.is_remote_frame))
        if self.wait and self.counter is not None and not self.deliver(self.drain_timeout):
            raise can.CanOperationError("in-process emulator did not take the frame within "
                                        f"{self.drain_timeout} s")
        if self.receive is not None:
            self.receive()                    # the emulator's answers: an SDO finds its response

    def recv(self, timeout: float | None = None) -> can.Message | None:
        """A lost link (a socketcand peer reset, an adapter gone) raises CanOperationError once,
        for the Notifier to hand to the listeners' `on_error`; after that the bus reads as
        silent, so the receive thread neither spins nor dies with a traceback."""
        if self.lost is not None:
            time.sleep(timeout or 0.0)
            return None
        frames = self._queue
        if timeout == 0.0 and frames is not None and self._plain():
            return _take(frames)
        try:
            return self.bus.recv(timeout)
        except (OSError, can.CanError) as exc:
            self.lost = exc
            raise can.CanOperationError(f"CAN link lost ({type(exc).__name__}: {exc})") from exc

    def _plain(self) -> bool:
        """An open virtual bus without filters or receive logging: what `recv(0)` returns is
        just the next frame of its queue (python-can's `BusABC.recv` would take it the same)."""
        bus = self.bus
        return (getattr(bus, "_open", False) and getattr(bus, "_filters", True) is None
                and not _CAN_BUS_LOG.isEnabledFor(bus.RECV_LOGGING_LEVEL))

    def fileno(self) -> int:
        raise NotImplementedError    # python-can's Notifier then reads in a thread

    @property
    def state(self):
        return self.bus.state

    def shutdown(self) -> None:
        self.bus.shutdown()


_CAN_BUS_LOG = logging.getLogger("can.bus")    # python-can's BusABC.recv logs each frame here


def _virtual_queue(bus: can.BusABC) -> queue.Queue | None:
    """The receive queue of python-can's in-process virtual bus (None for any other bus).

    Why: the lock-step drivers ask the bus for a frame a dozen times a tick, nearly always
    finding none; `BusABC.recv(0)` reads the clock twice and waits on the queue's condition to
    say so. Taking from the queue directly gives the same frames in the same order."""
    if type(bus).__name__ != "VirtualBus" or type(bus).__module__ != "can.interfaces.virtual":
        return None
    found = getattr(bus, "queue", None)
    return found if isinstance(found, queue.Queue) else None


def _take(frames: queue.Queue) -> can.Message | None:
    """The next frame waiting, or None at once."""
    if not frames.queue:
        return None
    try:
        return frames.get_nowait()
    except queue.Empty:
        return None


class Counted(can.Listener):
    """Counts frames once every listener before it has handled them (lock-step's `got`)."""

    def __init__(self, counter: ByteCounter) -> None:
        self.counter = counter

    def on_message_received(self, msg: can.Message) -> None:
        self.counter.got(1)


class LockStepReceiver:
    """The host side of lock-step on the in-process bus, read on the driver's own thread.

    `receive` reads every frame waiting on the bus (`recv` with timeout 0) and hands each to
    `listeners` in order, as python-can's Notifier would (canopen's MessageListener, `Counted`,
    ...; a listener's or the bus's exception goes to the listeners' `on_error`, and is raised
    if none has one). `DriverBus` calls it before each frame the driver sends (what is on the
    bus before ours is handled, and logged, first: the session log is in bus order) and after
    the emulator took the frame (an SDO request finds its response queued when `send`
    returns); the driver's `poll` calls `drain`.

    One thread reads at a time, and never waits for another to finish: a thread that finds
    the reader busy (another thread, or a listener that sent a frame) leaves its frames to it,
    and the reader reads once more before it lets go (`_wanted`). So nothing waits on a lock
    the reader's listeners may need, and the frames are handled in the order they came."""

    def __init__(self, bus: can.BusABC, listeners: list, counter: ByteCounter | None = None) -> None:
        self.bus = bus
        self.listeners = listeners          # the network's list, in the Notifier's order
        self.counter = counter              # the emulator's frames sent and handled, for `drain`
        self._reading = threading.Lock()
        self._wanted = False

    def receive(self) -> None:
        """Handle every frame waiting now (or leave them to the thread reading already)."""
        self._wanted = True
        while self._wanted:
            if not self._reading.acquire(blocking=False):
                return                       # the reader reads again before it lets go
            try:
                self._wanted = False
                self._read_waiting()
            finally:
                self._reading.release()

    def drain(self, timeout: float) -> bool:
        """Handle frames until every one the emulator counted as sent is handled (or `timeout` s
        passed: a frame still on its way from another thread)."""
        deadline = time.monotonic() + timeout
        while True:
            self.receive()
            if self.counter is None or self.counter.backlog() <= 0:
                return True
            remaining = deadline - time.monotonic()
            if remaining <= 0 or getattr(self.bus, "lost", None) is not None:
                return False                 # (a bus found lost brings nothing more: no wait)
            self.counter.wait_drained(min(remaining, 0.01))

    def _read_waiting(self) -> None:
        while True:
            try:
                msg = self.bus.recv(0.0)
                if msg is None:
                    return
                for listener in self.listeners:
                    listener.on_message_received(msg)
            except Exception as exc:          # as the Notifier: the listeners' on_error, else raise
                if not self._on_error(exc):
                    raise

    def _on_error(self, exc: Exception) -> bool:
        handled = False
        for listener in self.listeners:
            if hasattr(listener, "on_error"):
                try:
                    listener.on_error(exc)
                except NotImplementedError:
                    continue
                handled = True
        return handled
