"""The SICK LMS 2xx telegram protocol (LMS200, LMS291) over RS-232/RS-422, pure: bytes in/out.

A telegram: STX (02), an address byte (00 from the host; the LMS answers with its address
plus 80), a 16-bit length of the command byte and data (little-endian), the command byte, the
data, and a CRC-16 over everything before it (little-endian). A reply's last data byte is the
LMS's status. Before a reply to a command the LMS sends ACK (06); it answers a telegram it
cannot take (a bad CRC) with NAK (15). docs/lasers.md has the layouts and byte examples.

Units here are the protocol's: degrees, 1/100 degree, raw 13-bit range values in mm or cm.
"""
from __future__ import annotations

import re
import struct
from dataclasses import dataclass
from enum import IntEnum

import numpy as np

from robots.exceptions import CommandError, ProtocolError
from robots.link.parser import FramedParser, Reject

STX, ACK, NAK = 0x02, 0x06, 0x15
HOST_ADDRESS = 0x00            # the address byte of host telegrams (00 reaches the LMS)
REPLY_BIT = 0x80               # the LMS answers with its address | 80 and command | 80
MAX_LENGTH = 812 - 6           # the longest command+data the LMS sends (a 0.25 deg scan fits)
STATUS_OK = 0x10               # the status byte of a healthy LMS 2xx in the published replies
PASSWORD = b"SICK_LMS"         # installation mode's default password
CONFIG_LENGTH = 32             # the configuration block of 0x74/0x77
CONFIG_UNITS = 6               # its byte for the range unit (0 cm, 1 mm)
VALUE_MASK = 0x1FFF            # the 13 bits of a range value; the top 3 are flags
FIRST_ERROR_VALUE = 0x1FF7     # values from here up are no range: no echo, dazzling, ...
NO_ECHO = 0x1FFF


class Cmd(IntEnum):
    RESET = 0x10
    MODE = 0x20
    MEASURED_VALUES = 0x30
    STATUS = 0x31
    VARIANT = 0x3B
    PERMANENT_BAUD = 0x66
    READ_CONFIG = 0x74
    CONFIG = 0x77


class Reply(IntEnum):
    POWER_ON = 0x90
    RESET = 0x91
    NOT_ACKNOWLEDGED = 0x92
    MODE = 0xA0
    MEASURED_VALUES = 0xB0
    STATUS = 0xB1
    VARIANT = 0xBB
    PERMANENT_BAUD = 0xE6
    READ_CONFIG = 0xF4
    CONFIG = 0xF7


class Mode(IntEnum):
    INSTALLATION = 0x00
    CONTINUOUS = 0x24           # all measured values, continuously
    ON_REQUEST = 0x25           # measured values only on request (power-up mode)
    BAUD_38400 = 0x40
    BAUD_19200 = 0x41
    BAUD_9600 = 0x42
    BAUD_500000 = 0x48


BAUD_MODES = {9600: Mode.BAUD_9600, 19200: Mode.BAUD_19200, 38400: Mode.BAUD_38400,
              500000: Mode.BAUD_500000}
POWER_UP_BAUD = 9600
MODE_RESULTS = {0: "done", 1: "refused: wrong password", 2: "refused: LMS fault"}
# Angular range (deg) -> allowed resolutions (1/100 deg)
VARIANTS = {180: (100, 50), 100: (100, 50, 25)}
UNITS = {"cm": 0, "mm": 1}
UNIT_NAMES = {code: name for name, code in UNITS.items()}
UNIT_METRES = {"cm": 0.01, "mm": 0.001}


@dataclass(frozen=True)
class Telegram:
    """A checked telegram: `data` is what follows the command byte (a reply's status last)."""
    address: int
    command: int
    data: bytes = b""

    @property
    def payload(self) -> bytes:
        """A reply's data without its status byte."""
        return self.data[:-1]

    @property
    def status(self) -> int:
        """A reply's status byte."""
        return self.data[-1] if self.data else 0


@dataclass(frozen=True)
class Handshake:
    """A lone ACK (06) or NAK (15) between telegrams."""
    ack: bool


# -- CRC and framing ----------------------------------------------------------------------------
def crc16(data: bytes) -> int:
    """SICK's CRC-16 of a telegram (generator 8005, each step XORs in the byte pair
    (this byte, previous byte) as a 16-bit word), as the LMS 2xx telegram listing defines it."""
    crc, previous = 0, 0
    for byte in data:
        if crc & 0x8000:
            crc = ((crc & 0x7FFF) << 1) ^ 0x8005
        else:
            crc <<= 1
        crc ^= byte | (previous << 8)
        previous = byte
    return crc & 0xFFFF


def frame(command: int, data: bytes = b"", address: int = HOST_ADDRESS) -> bytes:
    """A whole telegram around a command (or reply) byte and its data."""
    length = 1 + len(data)
    if length > MAX_LENGTH:
        raise CommandError(f"LMS telegram of {length} bytes: length must be 1..{MAX_LENGTH}")
    body = bytes([STX, address]) + struct.pack("<H", length) + bytes([command]) + data
    return body + struct.pack("<H", crc16(body))


def _check(telegram: bytes) -> Telegram:
    if len(telegram) < 7 or telegram[0] != STX:
        raise Reject("length", f"byte 0: not a telegram ({len(telegram)} bytes, starting "
                               f"{telegram[:1].hex() or 'with nothing'})")
    length = telegram[2] | (telegram[3] << 8)
    if len(telegram) != length + 6:
        raise Reject("length", f"byte 2: length {length} does not match a telegram of "
                               f"{len(telegram)} bytes (expected {len(telegram) - 6})")
    want = crc16(telegram[:-2])
    got = telegram[-2] | (telegram[-1] << 8)
    if got != want:
        raise Reject("checksum", f"CRC at byte {len(telegram) - 2} of the telegram is "
                                 f"{got:04X}, expected {want:04X}")
    return Telegram(telegram[1], telegram[4], bytes(telegram[5:-2]))


def unframe(telegram: bytes) -> Telegram:
    """Check one whole telegram and split it. Raises ProtocolError with offset and reason."""
    try:
        return _check(bytes(telegram))
    except Reject as exc:
        raise ProtocolError(exc.reason) from None


class LMSParser(FramedParser):
    """Byte-fed parser for either direction: `feed(bytes)` -> [Telegram | Handshake].

    Between telegrams a lone ACK or NAK is a `Handshake`; any other stray byte is dropped
    and counted, and a telegram with a bad length or CRC costs its first byte (resync)."""
    header = bytes([STX])
    max_frame = MAX_LENGTH + 6

    def __init__(self, gap_timeout: float | None = 0.1) -> None:
        super().__init__(gap_timeout)
        # the newest CRC failure (resyncing inside a bad telegram overwrites last_error with
        # the lengths of bogus starts; this keeps what went wrong in the first place)
        self.last_crc_error = ""

    def _reject(self, exc: Reject, pos: int) -> int:
        if exc.kind == "checksum":
            self.last_crc_error = f"byte {self._base + pos}: {exc.reason}"
        return super()._reject(exc, pos)
    _starts = re.compile(b"[\x02\x06\x15]")

    def frame_length(self, buf, start):
        if len(buf) - start < 4:
            return None
        length = buf[start + 2] | (buf[start + 3] << 8)
        if not 1 <= length <= MAX_LENGTH:
            raise Reject("length", f"length {length} outside 1..{MAX_LENGTH}")
        return length + 6

    def decode(self, frame_bytes):
        return _check(frame_bytes)

    def _scan(self, packets: list) -> int:
        """As the base parser's scan, with ACK and NAK recognised between telegrams."""
        buf, pos = self._buf, 0
        while True:
            found = self._starts.search(buf, pos)
            if found is None:
                self._count_drop(len(buf) - pos)
                return len(buf)
            start = found.start()
            if start > pos:
                self._count_drop(start - pos)
            pos = start
            if buf[pos] != STX:
                packets.append(Handshake(buf[pos] == ACK))
                pos += 1
                continue
            after = self._take_frame(pos, packets)
            if after is None:
                return pos
            pos = after


# -- host telegrams ---------------------------------------------------------------------------
def set_mode(mode: int, password: bytes = b"") -> bytes:
    """0x20: change the operating mode (installation mode needs the password)."""
    if not 0 <= mode <= 0xFF:
        raise CommandError(f"LMS operating mode {mode}: allowed 0x00..0xFF")
    return frame(Cmd.MODE, bytes([mode]) + password)


def installation_mode(password: bytes = PASSWORD) -> bytes:
    if len(password) != 8:
        raise CommandError(f"LMS password {password!r}: allowed exactly 8 characters")
    return set_mode(Mode.INSTALLATION, password)


def baud_rate(baud: int) -> bytes:
    """0x20 with the mode that switches the line speed (the reply still comes at the old one)."""
    if baud not in BAUD_MODES:
        raise CommandError(f"LMS baud rate {baud}: allowed {', '.join(map(str, BAUD_MODES))}")
    return set_mode(BAUD_MODES[baud])


def request_measured_values() -> bytes:
    """0x30 01: one scan of all measured values."""
    return frame(Cmd.MEASURED_VALUES, b"\x01")


def request_status() -> bytes:
    return frame(Cmd.STATUS)


def set_variant(angle: int, resolution: int) -> bytes:
    """0x3B: angular range (deg) and resolution (1/100 deg), e.g. (180, 50)."""
    check_variant(angle, resolution)
    return frame(Cmd.VARIANT, struct.pack("<HH", angle, resolution))


def check_variant(angle: int, resolution: int) -> None:
    if angle not in VARIANTS:
        raise CommandError(f"LMS angular range {angle} deg: allowed "
                           f"{' or '.join(map(str, VARIANTS))}")
    if resolution not in VARIANTS[angle]:
        allowed = ", ".join(f"{r / 100:g}" for r in VARIANTS[angle])
        raise CommandError(f"LMS resolution {resolution / 100:g} deg at {angle} deg: "
                           f"allowed {allowed}")


def read_config() -> bytes:
    return frame(Cmd.READ_CONFIG)


def write_config(block: bytes) -> bytes:
    """0x77: the whole configuration block (installation mode only)."""
    if len(block) != CONFIG_LENGTH:
        raise CommandError(f"LMS configuration block of {len(block)} bytes: allowed "
                           f"exactly {CONFIG_LENGTH}")
    return frame(Cmd.CONFIG, bytes(block))


def with_units(block: bytes, units: str) -> bytes:
    """`block` with its range unit set to "mm" or "cm"."""
    if units not in UNITS:
        raise CommandError(f"LMS range unit {units!r}: allowed {', '.join(UNITS)}")
    out = bytearray(block)
    out[CONFIG_UNITS] = UNITS[units]
    return bytes(out)


def reset() -> bytes:
    return frame(Cmd.RESET)


# -- replies (LMS to host) --------------------------------------------------------------------
def reply(command: int, payload: bytes = b"", status: int = STATUS_OK,
          address: int = HOST_ADDRESS) -> bytes:
    """A reply telegram (the emulator's side): address | 80, the reply code, data, status."""
    return frame(command, bytes(payload) + bytes([status]), address | REPLY_BIT)


def mode_reply(result: int = 0, status: int = STATUS_OK) -> bytes:
    return reply(Reply.MODE, bytes([result]), status)


def variant_reply(ok: bool, angle: int, resolution: int, status: int = STATUS_OK) -> bytes:
    return reply(Reply.VARIANT, bytes([1 if ok else 0]) + struct.pack("<HH", angle, resolution),
                 status)


def measured_values_reply(values, units: str, status: int = STATUS_OK) -> bytes:
    """0xB0: the count word (bits 0-9 count, bits 14-15 unit) and the 13-bit values."""
    values = np.asarray(values, dtype=np.uint16)
    if len(values) > 0x3FF:
        raise CommandError(f"LMS scan of {len(values)} values: allowed at most {0x3FF}")
    count = len(values) | (UNITS[units] << 14)
    return reply(Reply.MEASURED_VALUES,
                 struct.pack("<H", count) + (values & VALUE_MASK).astype("<u2").tobytes(), status)


def decode_mode_reply(telegram: Telegram) -> int:
    """0xA0's result: 0 done, 1 wrong password, 2 LMS fault (see MODE_RESULTS)."""
    _expect(telegram, Reply.MODE, 1)
    return telegram.payload[0]


def decode_variant_reply(telegram: Telegram) -> tuple[bool, int, int]:
    """0xBB: (accepted, angle deg, resolution 1/100 deg)."""
    _expect(telegram, Reply.VARIANT, 5)
    ok, angle, resolution = struct.unpack_from("<BHH", telegram.payload)
    return bool(ok), angle, resolution


def decode_config(telegram: Telegram) -> tuple[bool, bytes]:
    """0xF4 (the block) or 0xF7 (accepted flag, then the block): (accepted, block)."""
    if telegram.command == Reply.READ_CONFIG:
        _expect(telegram, Reply.READ_CONFIG, CONFIG_LENGTH)
        return True, telegram.payload[:CONFIG_LENGTH]
    _expect(telegram, Reply.CONFIG, 1 + CONFIG_LENGTH)
    return bool(telegram.payload[0]), telegram.payload[1:1 + CONFIG_LENGTH]


@dataclass(frozen=True)
class MeasuredValues:
    """One scan as the LMS sent it: raw 13-bit values in `units`, the flag bits beside them."""
    values: np.ndarray          # uint16, 13-bit range values
    flags: np.ndarray           # uint8, bits 13-15 of each value
    units: str                  # "mm" or "cm"
    status: int

    def metres(self) -> np.ndarray:
        """Ranges in m; inf where the value is no range (no echo or an error code)."""
        ranges = self.values.astype(float) * UNIT_METRES[self.units]
        ranges[self.values >= FIRST_ERROR_VALUE] = np.inf
        return ranges


def decode_measured_values(telegram: Telegram) -> MeasuredValues:
    """0xB0: the scan. Raises ProtocolError when the count, unit or length do not fit."""
    _expect(telegram, Reply.MEASURED_VALUES, 2)
    payload = telegram.payload
    word = payload[0] | (payload[1] << 8)
    count, unit = word & 0x3FF, word >> 14
    if unit not in UNIT_NAMES:
        raise ProtocolError(f"LMS measured values: byte 6: unit bits {unit} are not a unit "
                            f"(0 cm, 1 mm)")
    if len(payload) != 2 + 2 * count:
        raise ProtocolError(f"LMS measured values: byte 5: {count} values need "
                            f"{2 + 2 * count} data bytes, the telegram has {len(payload)}")
    raw = np.frombuffer(payload, dtype="<u2", count=count, offset=2)
    return MeasuredValues(raw & VALUE_MASK, (raw >> 13).astype(np.uint8), UNIT_NAMES[unit],
                          telegram.status)


def _expect(telegram: Telegram, code: int, payload_at_least: int) -> None:
    if telegram.command != code:
        raise ProtocolError(f"LMS reply: byte 4: command {telegram.command:02X}, expected "
                            f"{code:02X}")
    if len(telegram.payload) < payload_at_least:
        raise ProtocolError(f"LMS reply {code:02X}: byte 5: {len(telegram.payload)} data "
                            f"bytes, expected at least {payload_at_least} and a status byte")


SWEEP = 1 / 75.0               # s, one mirror revolution
BITS_PER_BYTE = 10             # start, 8 data, stop


def value_count(angle: int, resolution: int) -> int:
    """Values in one scan, e.g. 361 at 180 deg / 0.5 deg."""
    return angle * 100 // resolution + 1


def scan_period(angle: int, resolution: int, baud: int) -> float:
    """s per scan: the sweeps an interlaced scan takes (2 at 0.5 deg, 4 at 0.25 deg), or the
    line's time for the 0xB0 telegram at `baud` when that is longer."""
    sweeps = {100: 1, 50: 2, 25: 4}[resolution]
    telegram = 6 + 1 + 2 + 2 * value_count(angle, resolution) + 1
    return max(sweeps * SWEEP, telegram * BITS_PER_BYTE / baud)


def scan_angles(angle: int, resolution: int) -> np.ndarray:
    """The beams' angles (rad) in the laser's frame, x forward: the LMS counts from its right
    (0 deg) counter-clockwise; a 100 deg scan covers 40..140 deg."""
    start = (180 - angle) / 2
    degrees = start + np.arange(value_count(angle, resolution)) * resolution / 100.0 - 90.0
    return np.radians(degrees)
