"""A byte-fed parser for framed packets (header, length, check), shared by the serial drivers.

Why: every driver needs the same guarantees from its receive path. `feed` never blocks and may
get any chunking of the stream; the buffer never holds more than one unfinished frame; a bad
frame costs only its first byte, after which the parser resynchronises on the next header; a
frame left unfinished by a silent gap on the line is dropped (ARIA's inter-byte timeout); and
everything dropped is counted, with the stream offset and reason of the last drop, so a flaky
cable shows up in numbers rather than in odd behaviour.

A protocol subclasses `FramedParser`, sets `header` and `max_frame`, and implements
`frame_length` and `decode`; both raise `Reject` for what is not a valid frame.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any


class Reject(Exception):
    """A candidate frame is not valid. `kind` is "length" or "checksum" (or a protocol's own)."""

    def __init__(self, kind: str, reason: str) -> None:
        super().__init__(reason)
        self.kind = kind
        self.reason = reason


@dataclass
class ParserStats:
    """What went through a parser, and what it threw away."""
    bytes_in: int = 0
    packets: int = 0
    dropped_bytes: int = 0     # bytes that were not part of any accepted packet
    bad_length: int = 0        # frames rejected for their length/count field
    bad_checksum: int = 0      # frames rejected by their check
    bad_other: int = 0         # frames rejected for a protocol-specific reason
    gaps: int = 0              # unfinished frames dropped after a silent gap on the line
    overruns: int = 0          # times the driver fell behind and left older bytes out
    last_error: str = ""       # "byte <offset>: <reason>" of the newest drop

    @property
    def rejected(self) -> int:
        return self.bad_length + self.bad_checksum + self.bad_other + self.gaps


class FramedParser(ABC):
    """Feed bytes in any chunks, get whole decoded packets out, in order."""

    header: bytes = b""
    max_frame: int = 256

    def __init__(self, gap_timeout: float | None = 0.1) -> None:
        self.gap_timeout = gap_timeout
        self.stats = ParserStats()
        self._buf = bytearray()
        self._base = 0                 # stream offset of _buf[0]
        self._last_time: float | None = None

    @abstractmethod
    def frame_length(self, buf: bytearray, start: int) -> int | None:
        """Total length of the frame whose header starts at `start`; None if more bytes are needed."""

    @abstractmethod
    def decode(self, frame: bytes) -> Any:
        """Check a whole frame and turn it into a packet."""

    def reset(self) -> None:
        """Forget any unfinished frame (e.g. after reopening the port); counters stay."""
        self._drop_all("reset")

    @property
    def pending(self) -> int:
        """Bytes held back waiting for the rest of a frame (never more than `max_frame`)."""
        return len(self._buf)

    def feed(self, data: bytes, now: float | None = None) -> list:
        """Parse `data`; return the packets it completed. `now` enables the silent-gap rule."""
        if now is not None:
            self._expire_gap(now)
            self._last_time = now
        self.stats.bytes_in += len(data)
        self._buf += data
        packets: list = []
        pos = self._scan(packets)
        self._consume(pos)
        return packets

    def feed_newest(self, data: bytes, keep: int, now: float | None = None) -> list:
        """Like `feed`, but of more than `keep` bytes that arrived at once only the newest
        `keep` are parsed (a flood: the robot's present state, not a backlog of the past)."""
        return self.feed(self.skip_older(data, keep), now)

    def skip_older(self, data: bytes, keep: int) -> bytes:
        """The newest `keep` bytes of `data`; the older ones and any unfinished frame are
        counted as dropped (an overrun, with the stream offset), never parsed."""
        if len(data) <= keep:
            return data
        skipped = len(data) - keep
        self.stats.overruns += 1
        self._drop_all("")
        self.stats.last_error = (f"byte {self._base}: overrun: {skipped} bytes left out, "
                                 f"older than the newest {keep} that arrived at once")
        self.stats.bytes_in += skipped
        self._count_drop(skipped)
        self._base += skipped
        return data[skipped:]

    def _expire_gap(self, now: float) -> None:
        if (self._buf and self.gap_timeout is not None and self._last_time is not None
                and now - self._last_time > self.gap_timeout):
            self.stats.gaps += 1
            self._drop_all(f"unfinished frame after a {now - self._last_time:.3f} s gap")

    def _scan(self, packets: list) -> int:
        """Decode frames from the buffer; return how many leading bytes are consumed."""
        buf, header = self._buf, self.header
        pos = 0
        while True:
            start = buf.find(header, pos)
            if start < 0:
                return self._keep_header_prefix(pos)
            if start > pos:
                self._count_drop(start - pos)
            pos = self._take_frame(start, packets)
            if pos is None:
                return start

    def _take_frame(self, pos: int, packets: list) -> int | None:
        """Decode the frame starting at `pos` (append it to `packets`, or count its rejection);
        return where scanning goes on, or None while the frame is still incomplete."""
        buf = self._buf
        try:
            length = self.frame_length(buf, pos)
        except Reject as exc:
            return self._reject(exc, pos)
        if length is None or len(buf) - pos < length:
            return None
        try:
            packet = self.decode(bytes(buf[pos:pos + length]))
        except Reject as exc:
            return self._reject(exc, pos)
        packets.append(packet)
        self.stats.packets += 1
        return pos + length

    def _keep_header_prefix(self, pos: int) -> int:
        """Keep a trailing partial header (it may complete with the next chunk); drop the rest."""
        end = len(self._buf)
        keep = 0
        for n in range(min(len(self.header) - 1, end - pos), 0, -1):
            if self._buf[end - n:] == self.header[:n]:
                keep = n
                break
        self._count_drop(end - keep - pos)
        return end - keep

    def _reject(self, exc: Reject, pos: int) -> int:
        counter = {"length": "bad_length", "checksum": "bad_checksum"}.get(exc.kind, "bad_other")
        setattr(self.stats, counter, getattr(self.stats, counter) + 1)
        self.stats.last_error = f"byte {self._base + pos}: {exc.reason}"
        self._count_drop(1)
        return pos + 1

    def _count_drop(self, n: int) -> None:
        self.stats.dropped_bytes += n

    def _consume(self, pos: int) -> None:
        if pos:
            del self._buf[:pos]
            self._base += pos

    def _drop_all(self, reason: str) -> None:
        if self._buf:
            self.stats.last_error = f"byte {self._base}: {reason}"
            self._count_drop(len(self._buf))
            self._consume(len(self._buf))
