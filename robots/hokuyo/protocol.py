"""SCIP 2.0, the command protocol of Hokuyo laser scanners (URG, UST, UTM), pure: bytes in/out.

Everything is printable ASCII in lines ending with LF. The host sends a command line: a
two-letter symbol, fixed-width decimal parameters and optionally ";" and a tag of up to 16
characters that comes back in the echo. The sensor answers with a block of lines ended by an
empty line: the echo of the command, a status line (two characters and their check
character), then data lines, each followed by its check character. The check character of a
line is the sum of its bytes, lower 6 bits, plus 30 hex; in VEND:/PROD:-style information lines
it covers the text before the ";" only.

Numbers in data are 6-bit characters (value + 30 hex): ranges in 2 characters (MS/GS) or 3
(MD/GD), the time stamp in 4. A scan's characters run on across lines of 64. docs/lasers.md.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from robots.exceptions import CommandError, ProtocolError
from robots.link.parser import ParserStats

LF = b"\n"
LINE_WIDTH = 64                     # data characters per line before its check character
MAX_BLOCK = 8192                    # bytes: longer than any reply (1081 steps x 3 chars fit)
MAX_TAG = 16
STATUS_OK, STATUS_STREAM = "00", "99"
STATUS_LASER_ALREADY_ON = "02"       # BM's answer when the laser is on
STATUS_UNKNOWN_COMMAND = "0E"        # our emulator's answer to an unknown symbol (see docs)
_TAG = re.compile(r"[A-Za-z0-9 ._+@]{1,16}")


# -- characters and checks ------------------------------------------------------------------------
def check_char(text: bytes | str) -> str:
    """The check character of `text`: the sum of its bytes, lower 6 bits, plus 30 hex."""
    data = text.encode("ascii") if isinstance(text, str) else text
    return chr((sum(data) & 0x3F) + 0x30)


def encode(value: int, chars: int) -> str:
    """`value` in `chars` 6-bit characters, high part first (e.g. 1234 -> "CB")."""
    if not 0 <= value < 1 << (6 * chars):
        raise CommandError(f"SCIP value {value}: allowed 0..{(1 << (6 * chars)) - 1} in "
                           f"{chars} characters")
    return "".join(chr(((value >> (6 * (chars - 1 - i))) & 0x3F) + 0x30) for i in range(chars))


def decode(text: str) -> int:
    """The value of 6-bit characters (e.g. "1Dh" -> 5432). Raises ProtocolError."""
    value = 0
    for i, char in enumerate(text):
        code = ord(char) - 0x30
        if not 0 <= code < 64:
            raise ProtocolError(f"SCIP number {text!r}: character {i} ({char!r}) is not a "
                                f"6-bit character (30..6F hex)")
        value = (value << 6) | code
    return value


def decode_array(text: str, chars: int) -> np.ndarray:
    """A run of `chars`-character values (a scan), vectorised."""
    if len(text) % chars:
        raise ProtocolError(f"SCIP data of {len(text)} characters is not a whole number of "
                            f"{chars}-character values")
    codes = np.frombuffer(text.encode("ascii"), dtype=np.uint8).astype(np.int64) - 0x30
    if len(codes) and (codes.min() < 0 or codes.max() > 63):
        bad = int(np.flatnonzero((codes < 0) | (codes > 63))[0])
        raise ProtocolError(f"SCIP data: character {bad} ({text[bad]!r}) is not a 6-bit "
                            f"character")
    codes = codes.reshape(-1, chars)
    weights = 1 << (6 * np.arange(chars - 1, -1, -1))
    return codes @ weights


def encode_array(values, chars: int) -> str:
    values = np.asarray(values, dtype=np.int64)
    shifts = 6 * np.arange(chars - 1, -1, -1)
    codes = ((values[:, None] >> shifts) & 0x3F) + 0x30
    return codes.astype(np.uint8).tobytes().decode("ascii")


# -- host commands ------------------------------------------------------------------------------
def command(symbol: str, parameters: str = "", tag: str = "") -> bytes:
    """A command line: symbol, parameters, optional ";tag", LF."""
    if tag and not _TAG.fullmatch(tag):
        raise CommandError(f"SCIP tag {tag!r}: allowed 1..{MAX_TAG} letters, digits, space "
                           f"and . _ + @")
    return (symbol + parameters + (";" + tag if tag else "")).encode("ascii") + LF


def _steps(start: int, end: int, cluster: int) -> str:
    for name, value, top in (("start step", start, 9999), ("end step", end, 9999),
                             ("cluster count", cluster, 99)):
        if not 0 <= value <= top:
            raise CommandError(f"SCIP {name} {value}: allowed 0..{top}")
    if end < start:
        raise CommandError(f"SCIP end step {end}: allowed {start}..9999 (not below the start)")
    return f"{start:04d}{end:04d}{cluster:02d}"


def md(start: int, end: int, cluster: int = 1, interval: int = 0, scans: int = 0,
       tag: str = "", three_chars: bool = True) -> bytes:
    """MD (3-character ranges) or MS (2-character): stream `scans` scans (0 = until QT),
    skipping `interval` scans between two sent."""
    if not 0 <= interval <= 9:
        raise CommandError(f"SCIP scan interval {interval}: allowed 0..9")
    if not 0 <= scans <= 99:
        raise CommandError(f"SCIP number of scans {scans}: allowed 0..99 (0: until QT)")
    return command("MD" if three_chars else "MS",
                   _steps(start, end, cluster) + f"{interval:01d}{scans:02d}", tag)


def gd(start: int, end: int, cluster: int = 1, tag: str = "", three_chars: bool = True) -> bytes:
    """GD (3-character ranges) or GS (2-character): the newest scan once."""
    return command("GD" if three_chars else "GS", _steps(start, end, cluster), tag)


def laser_on() -> bytes:
    return command("BM")


def stop() -> bytes:
    """QT: laser off, streaming stopped."""
    return command("QT")


def version() -> bytes:
    return command("VV")


def parameters() -> bytes:
    return command("PP")


def state() -> bytes:
    return command("II")


def reset() -> bytes:
    return command("RS")


# -- replies ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Reply:
    """One checked reply block: the echo, the status, the data lines without their checks."""
    echo: str
    status: str
    lines: tuple[str, ...] = ()

    @property
    def symbol(self) -> str:
        return self.echo[:2]

    def info(self) -> dict[str, str]:
        """VV/PP/II lines "KEY:value;" as a dict (checked with the information-line rule)."""
        out = {}
        for line in self.lines:
            key, _, value = line.partition(":")
            out[key] = value.removesuffix(";")
        return out


def reply(echo: str, status: str, lines=(), info: bool = False) -> bytes:
    """A reply block (the sensor's side): echo, status with its check, data lines, empty line."""
    out = [echo, status + check_char(status)]
    for line in lines:
        body = line[:-1] if info and line.endswith(";") else line
        out.append(line + check_char(body))
    return ("\n".join(out) + "\n\n").encode("ascii")


def info_lines(pairs: dict[str, str]) -> list[str]:
    return [f"{key}:{value};" for key, value in pairs.items()]


def split_data(text: str) -> list[str]:
    """A scan's characters as lines of at most 64 (the last shorter)."""
    return [text[i:i + LINE_WIDTH] for i in range(0, len(text), LINE_WIDTH)] or [""]


def scan_reply(echo: str, status: str, timestamp: int, values, three_chars: bool = True) -> bytes:
    """An MD/MS/GD/GS scan block: echo, status, time stamp, the ranges over lines of 64."""
    data = encode_array(values, 3 if three_chars else 2)
    return reply(echo, status, [encode(timestamp & 0xFFFFFF, 4)] + split_data(data))


def parse_block(block: bytes, offset: int = 0, info: bool | None = None) -> Reply:
    """Check one reply block (its lines, without the final empty line) and split it.

    `info` picks the check rule of the data lines (None: by the echo's symbol: VV, PP, II).
    Raises ProtocolError with the stream byte offset (`offset` + the block's) and reason."""
    try:
        text = block.decode("ascii")
    except UnicodeDecodeError as exc:
        raise ProtocolError(f"byte {offset + exc.start}: not ASCII ({block[exc.start]:#04x})") \
            from None
    lines = text.split("\n")
    if len(lines) < 2:
        raise ProtocolError(f"byte {offset}: a reply needs an echo and a status line, got "
                            f"{len(lines)} line(s)")
    echo, status_line = lines[0], lines[1]
    position = offset + len(echo) + 1
    if len(status_line) != 3 or check_char(status_line[:2]) != status_line[2]:
        raise ProtocolError(f"byte {position}: status line {status_line!r} is not two "
                            f"characters and their check character")
    if info is None:
        info = echo[:2] in ("VV", "PP", "II")
    data = []
    position += len(status_line) + 1
    for number, line in enumerate(lines[2:], start=3):
        body = line[:-1]
        checked = body[:-1] if info and body.endswith(";") else body
        if not line or check_char(checked) != line[-1]:
            want = check_char(checked) if line else "?"
            raise ProtocolError(f"byte {position + max(0, len(line) - 1)}: line {number} check "
                                f"character {line[-1:]!r}, expected {want!r}")
        data.append(body)
        position += len(line) + 1
    return Reply(echo, status_line[:2], tuple(data))


@dataclass(frozen=True)
class Scan:
    """One decoded scan: the time stamp (ms, 24 bits) and the range values (mm)."""
    timestamp: int
    values: np.ndarray
    remaining: int | None = None        # MD/MS: scans still to come (None: GD/GS or unlimited)


def decode_scan(block: Reply) -> Scan:
    """An MD/MS/GD/GS data block (status 99 for MD/MS, 00 for GD/GS)."""
    symbol = block.symbol
    if symbol not in ("MD", "MS", "GD", "GS"):
        raise ProtocolError(f"SCIP scan: echo {block.echo!r} is not MD, MS, GD or GS")
    if len(block.lines) < 1 or len(block.lines[0]) != 4:
        raise ProtocolError(f"SCIP {symbol} scan: the first data line must be a 4-character "
                            f"time stamp")
    chars = 3 if symbol in ("MD", "GD") else 2
    values = decode_array("".join(block.lines[1:]), chars)
    remaining = None
    if symbol in ("MD", "MS") and len(block.echo) >= 15 and block.echo[13:15].isdigit():
        remaining = int(block.echo[13:15])
    return Scan(decode(block.lines[0]), values, remaining)


# -- the byte stream -----------------------------------------------------------------------------
@dataclass
class ScipParser:
    """Byte-fed: `feed(bytes)` -> [Reply]. Blocks end with an empty line; a block that does not
    check costs itself (counted, with offset and reason); bytes that end no block within
    MAX_BLOCK are dropped (noise on the line)."""
    stats: ParserStats = field(default_factory=ParserStats)
    _buf: bytearray = field(default_factory=bytearray)
    _base: int = 0

    def reset(self) -> None:
        if self._buf:
            self._drop(len(self._buf), "reset")

    def feed(self, data: bytes) -> list[Reply]:
        self.stats.bytes_in += len(data)
        self._buf += data
        out: list[Reply] = []
        while True:
            end = self._buf.find(b"\n\n")
            if end < 0:
                break
            block = bytes(self._buf[:end])
            start = self._leading_noise(block)
            try:
                out.append(parse_block(block[start:], self._base + start))
                self.stats.packets += 1
                self.stats.dropped_bytes += start
            except ProtocolError as exc:
                self._reject(str(exc))
                self.stats.dropped_bytes += end
            del self._buf[:end + 2]
            self._base += end + 2
        if len(self._buf) > MAX_BLOCK:
            keep = self._buf.rfind(b"\n") + 1 or len(self._buf)
            self._drop(keep, f"{keep} bytes that end no reply")
        return out

    def skip_older(self, data: bytes, keep: int) -> bytes:
        """The newest `keep` bytes of `data` from the first block boundary in them; the rest
        and any unfinished block are counted as dropped (an overrun), never parsed."""
        if len(data) <= keep:
            return data
        start = len(data) - keep
        boundary = data.find(b"\n\n", start)
        start = len(data) if boundary < 0 else boundary + 2
        if self._buf:
            self._drop(len(self._buf), "overrun")
        self.stats.overruns += 1
        self.stats.last_error = (f"byte {self._base}: overrun: {start} bytes left out, older "
                                 f"than the newest {keep} that arrived at once")
        self.stats.bytes_in += start
        self.stats.dropped_bytes += start
        self._base += start
        return data[start:]

    @staticmethod
    def _leading_noise(block: bytes) -> int:
        """Where the block's echo starts: after stray non-printable bytes before it."""
        start = 0
        while start < len(block) and not 0x20 <= block[start] < 0x7F:
            start += 1
        return start

    def _reject(self, reason: str) -> None:
        if "check character" in reason:
            self.stats.bad_checksum += 1
        else:
            self.stats.bad_other += 1
        self.stats.last_error = reason

    def _drop(self, n: int, why: str) -> None:
        self.stats.bad_other += 1
        self.stats.last_error = f"byte {self._base}: {why}"
        self.stats.dropped_bytes += n
        del self._buf[:n]
        self._base += n

    @property
    def pending(self) -> int:
        return len(self._buf)
