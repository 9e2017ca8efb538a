"""Reading what has arrived: every byte in one call, whatever the transport.

Why: a driver decides its link is alive by the age of the newest good packet. That only holds
if it reads as fast as bytes arrive. pyserial's `socket://` reports one byte waiting whatever
is there (so `read(in_waiting)` takes one byte a call), and a robot end that floods the line
(thousands of queued status packets, or a second of packets back to back) then leaves a backlog
the driver works through for seconds, each stale packet counting as fresh, so a robot that fell
silent after the flood looks alive long after it stopped talking.

`read_arrived` returns everything the port holds (waiting up to `timeout` for the first byte),
on a tty, a pty or a socket alike. A driver then hands it to `FramedParser.feed_newest`, which
parses only the newest bytes of a flood (the robot's present state, not a backlog of the past)
and counts the rest as dropped (an overrun, with the stream offset): nothing is lost silently,
and each read costs a bounded time, so the newest packet's age is the age of what arrived.
"""
from __future__ import annotations

import select

import serial

READ_LIMIT = 1 << 22        # bytes one call takes at most (a socket's whole buffer, in practice)


def read_arrived(port: serial.SerialBase, timeout: float, limit: int = READ_LIMIT) -> bytes:
    """Every byte that has arrived, or wait up to `timeout` s for the first one. Raises
    serial.SerialException (or OSError) when the port is gone or the other end hung up."""
    sock = getattr(port, "_socket", None)       # pyserial's socket:// keeps it here
    if sock is not None:
        return _read_socket(sock, timeout, limit)
    if port.timeout != timeout:                 # setting it reconfigures the tty: only on change
        port.timeout = timeout
    data = port.read(max(1, min(limit, port.in_waiting)))
    if data:
        more = port.in_waiting                  # what came while the first read returned
        while more and len(data) < limit:
            data += port.read(min(more, limit - len(data)))
            more = port.in_waiting
    return data


def _read_socket(sock, timeout: float, limit: int) -> bytes:
    ready, _, _ = select.select([sock], [], [], timeout)
    if not ready:
        return b""
    chunks = []
    size = 0
    while size < limit:
        try:
            chunk = sock.recv(min(1 << 20, limit - size), _DONTWAIT)
        except (BlockingIOError, InterruptedError):
            break                               # all that has arrived is read
        if not chunk:
            if chunks:
                break                           # hand over what came; the next call raises
            raise serial.SerialException("the other end closed the connection")
        chunks.append(chunk)
        size += len(chunk)
        if not _DONTWAIT:
            break                               # no non-blocking recv here: one chunk a call
    return b"".join(chunks)


try:                                            # MSG_DONTWAIT: a non-blocking recv on a
    from socket import MSG_DONTWAIT as _DONTWAIT  # blocking socket (POSIX)
except ImportError:                             # pragma: no cover - not on POSIX
    _DONTWAIT = 0


class StampedArrival:
    """When a stamped message arrived, on the monotonic clock, from the stamp its source or
    interface gave it (wall-clock seconds, as python-can's `Message.timestamp`).

    Why: a driver that handles messages behind a queue (a CAN notifier working through a
    flood) must not take a message's handling time for its arrival, or a backlog of old
    heartbeats keeps a dead node alive. The stamp's clock may be another machine's (a
    socketcand server), so its offset is learnt as the smallest delay seen (a message handled
    at once), allowed to creep up by `drift` s per s so a clock step is forgotten in time.
    A message without a stamp counts as arriving when it is handled."""

    def __init__(self, drift: float = 0.01) -> None:
        self.drift = drift
        self._offset: float | None = None      # smallest (wall now - stamp) seen, s
        self._offset_at = 0.0                  # monotonic time it was last lowered or crept

    def arrived(self, stamp: float | None, wall_now: float, now: float) -> float:
        """The monotonic arrival time of a message stamped `stamp`, handled at `now`
        (monotonic) / `wall_now` (wall clock)."""
        if not stamp:
            return now
        delay = wall_now - stamp
        if self._offset is None:
            self._offset = delay
        else:
            self._offset += self.drift * max(0.0, now - self._offset_at)
            self._offset = min(self._offset, delay)
        self._offset_at = now
        return now - max(0.0, delay - self._offset)
