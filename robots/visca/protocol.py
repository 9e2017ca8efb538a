"""The Sony VISCA protocol as the EVI-D31 and EVI-D70 pan-tilt cameras speak it: pure bytes in/out.

A packet is a header byte, a message and the terminator FF, 3 to 16 bytes. The controller's
header is 8x (x = the camera's address 1..7, 8 = broadcast); the camera's is z0 with z = its
address + 8 (90 for camera 1). A command is acknowledged (z0 4y FF, y = the socket 1 or 2 it
occupies) and later completed (z0 5y FF), or refused with an error (z0 6y EE FF). An inquiry
is answered at once with z0 50 and its data. Positions travel as four nibbles (0p 0q 0r 0s,
a 16-bit two's complement number, most significant first). Our notes with byte examples:
docs/visca.md. Nothing here does I/O; the driver and the emulator do.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum, IntEnum

from robots.exceptions import CommandError, ProtocolError
from robots.link.parser import FramedParser, Reject

TERMINATOR = 0xFF
BROADCAST = 0x88                 # header of a packet for every device on the daisy chain
MAX_PACKET = 16                  # bytes, header and terminator included
MIN_PACKET = 3
SOCKETS = (1, 2)                 # a camera executes at most two commands at once
ADDRESSES = range(1, 8)


class ErrorCode(IntEnum):
    """The third byte of an error reply z0 6y EE FF."""
    MESSAGE_LENGTH = 0x01
    SYNTAX = 0x02                # bad format or a parameter out of range
    BUFFER_FULL = 0x03           # both sockets busy
    CANCELLED = 0x04             # the cancelled command ends here; no completion follows
    NO_SOCKET = 0x05             # nothing to cancel in that socket (or a bad socket number)
    NOT_EXECUTABLE = 0x41        # the command does not fit the camera's current state


ERROR_NAMES = {ErrorCode.MESSAGE_LENGTH: "message length error", ErrorCode.SYNTAX: "syntax error",
               ErrorCode.BUFFER_FULL: "command buffer full", ErrorCode.CANCELLED: "command cancelled",
               ErrorCode.NO_SOCKET: "no socket", ErrorCode.NOT_EXECUTABLE: "command not executable"}


class Direction(Enum):
    """Pan-tiltDrive's last two bytes: (pan, tilt); pan 01 left, 02 right; tilt 01 up, 02 down;
    03 holds that axis still."""
    UP = (0x03, 0x01)
    DOWN = (0x03, 0x02)
    LEFT = (0x01, 0x03)
    RIGHT = (0x02, 0x03)
    UP_LEFT = (0x01, 0x01)
    UP_RIGHT = (0x02, 0x01)
    DOWN_LEFT = (0x01, 0x02)
    DOWN_RIGHT = (0x02, 0x02)
    STOP = (0x03, 0x03)

    @property
    def pan_sign(self) -> int:
        return {0x01: -1, 0x02: 1, 0x03: 0}[self.value[0]]

    @property
    def tilt_sign(self) -> int:
        return {0x01: 1, 0x02: -1, 0x03: 0}[self.value[1]]


# -- the cameras ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Model:
    """What one camera model accepts: position ranges in its units and its speed codes.

    `pan_deg_s[i]` is the speed of code i + 1 in deg/s. Pan to the right and tilt up are
    positive, as on the camera."""
    name: str
    model_id: int                       # CAM_VersionInq's HHHH
    pan_range: tuple[int, int]          # units
    tilt_range: tuple[int, int]
    pan_range_deg: tuple[float, float]
    tilt_range_deg: tuple[float, float]
    pan_deg_s: tuple[float, ...]
    tilt_deg_s: tuple[float, ...]
    vendor_id: int = 0x0020

    @property
    def pan_units_per_deg(self) -> float:
        return self.pan_range[1] / self.pan_range_deg[1]

    @property
    def tilt_units_per_deg(self) -> float:
        return self.tilt_range[1] / self.tilt_range_deg[1]

    @property
    def max_pan_speed(self) -> int:
        return len(self.pan_deg_s)

    @property
    def max_tilt_speed(self) -> int:
        return len(self.tilt_deg_s)


# EVI-D30/D31: pan FC90..0370 (-100..+100 deg), tilt FED4..012C (-25..+25 deg); pan speeds
# 01..18 at 3.3 deg/s a step (80 deg/s), tilt 01..14 at 2.5 deg/s a step (50 deg/s).
EVI_D31 = Model("evi-d31", 0x0402, (-0x370, 0x370), (-0x12C, 0x12C), (-100.0, 100.0),
                (-25.0, 25.0), tuple(80.0 * n / 24 for n in range(1, 0x19)),
                tuple(2.5 * n for n in range(1, 0x15)))
# EVI-D70: pan F725..08DB (-170..+170 deg), tilt FE70..04B0 (-30..+90 deg); pan speeds 01..18,
# tilt 01..17. Its speed table is not in our notes: assumed linear up to 100 and 90 deg/s.
EVI_D70 = Model("evi-d70", 0x040E, (-0x8DB, 0x8DB), (-0x190, 0x4B0), (-170.0, 170.0),
                (-30.0, 90.0), tuple(100.0 * n / 24 for n in range(1, 0x19)),
                tuple(90.0 * n / 23 for n in range(1, 0x18)))
MODELS = {m.name: m for m in (EVI_D31, EVI_D70)}


def model_named(name: str) -> Model:
    try:
        return MODELS[name.strip().lower()]
    except KeyError:
        raise CommandError(f"VISCA model {name!r}: known models {', '.join(sorted(MODELS))}") from None


def units_of(model: Model, pan_rad: float, tilt_rad: float) -> tuple[int, int]:
    """Camera units for a (pan, tilt) in rad, rounded and kept inside the model's ranges."""
    pan = round(math.degrees(pan_rad) * model.pan_units_per_deg)
    tilt = round(math.degrees(tilt_rad) * model.tilt_units_per_deg)
    return (min(max(pan, model.pan_range[0]), model.pan_range[1]),
            min(max(tilt, model.tilt_range[0]), model.tilt_range[1]))


def radians_of(model: Model, pan: int, tilt: int) -> tuple[float, float]:
    """(pan, tilt) in rad for camera units."""
    return (math.radians(pan / model.pan_units_per_deg),
            math.radians(tilt / model.tilt_units_per_deg))


def speed_code(table: tuple[float, ...], rate_deg_s: float) -> int:
    """The fastest code whose speed does not exceed `rate_deg_s` (at least code 1)."""
    code = 1
    for i, speed in enumerate(table, start=1):
        if speed <= rate_deg_s + 1e-9:
            code = i
    return code


# -- nibbles ----------------------------------------------------------------------------------------
def nibbles(value: int) -> bytes:
    """A signed 16-bit value as four bytes 0p 0q 0r 0s, most significant nibble first."""
    value = int(value)
    if not -0x8000 <= value <= 0x7FFF:
        raise CommandError(f"VISCA position {value}: allowed -32768..32767")
    word = value & 0xFFFF
    return bytes((word >> shift) & 0x0F for shift in (12, 8, 4, 0))


def from_nibbles(data: bytes) -> int:
    """The signed value of four nibble bytes; each byte must be 00..0F."""
    if len(data) != 4 or any(b > 0x0F for b in data):
        raise ProtocolError(f"position nibbles {data.hex(' ')}: expected four bytes 00..0F")
    word = (data[0] << 12) | (data[1] << 8) | (data[2] << 4) | data[3]
    return word - 0x10000 if word & 0x8000 else word


# -- controller to camera ---------------------------------------------------------------------------
def _header(address: int) -> int:
    if address not in ADDRESSES:
        raise CommandError(f"VISCA address {address}: allowed 1..7")
    return 0x80 | address


def _speed(name: str, value: int, top: int) -> int:
    value = int(value)
    if not 1 <= value <= top:
        raise CommandError(f"VISCA {name} {value:#04x}: allowed 0x01..{top:#04x}")
    return value


def address_set() -> bytes:
    """AddressSet, broadcast: the first camera takes address 1 and passes 2 on."""
    return bytes((BROADCAST, 0x30, 0x01, TERMINATOR))


def if_clear(address: int | None = None) -> bytes:
    """IF_Clear: empty the command buffers, cancel what runs; broadcast when no address."""
    head = BROADCAST if address is None else _header(address)
    return bytes((head, 0x01, 0x00, 0x01, TERMINATOR))


def cancel(address: int, socket: int) -> bytes:
    """Cancel the command running in `socket` (8x 2p FF)."""
    if socket not in SOCKETS:
        raise CommandError(f"VISCA cancel socket {socket}: allowed 1..2")
    return bytes((_header(address), 0x20 | socket, TERMINATOR))


def pan_tilt_drive(address: int, direction: Direction, pan_speed: int, tilt_speed: int,
                   model: Model = EVI_D31) -> bytes:
    """Pan-tiltDrive: move in `direction` until Stop or a limit (8x 01 06 01 VV WW pp tt FF)."""
    return bytes((_header(address), 0x01, 0x06, 0x01,
                  _speed("pan speed", pan_speed, model.max_pan_speed),
                  _speed("tilt speed", tilt_speed, model.max_tilt_speed),
                  *direction.value, TERMINATOR))


def _position_command(code: int, address: int, pan_speed: int, tilt_speed: int, pan: int,
                      tilt: int, model: Model) -> bytes:
    return (bytes((_header(address), 0x01, 0x06, code,
                   _speed("pan speed", pan_speed, model.max_pan_speed),
                   _speed("tilt speed", tilt_speed, model.max_tilt_speed)))
            + nibbles(pan) + nibbles(tilt) + bytes((TERMINATOR,)))


def absolute_position(address: int, pan_speed: int, tilt_speed: int, pan: int, tilt: int,
                      model: Model = EVI_D31) -> bytes:
    """Pan-tiltDrive AbsolutePosition (8x 01 06 02 VV WW 0Y0Y0Y0Y 0Z0Z0Z0Z FF), in camera units."""
    for axis, value, (low, high) in (("pan", pan, model.pan_range), ("tilt", tilt, model.tilt_range)):
        if not low <= value <= high:
            raise CommandError(f"VISCA {model.name} {axis} position {value}: allowed {low}..{high}")
    return _position_command(0x02, address, pan_speed, tilt_speed, pan, tilt, model)


def relative_position(address: int, pan_speed: int, tilt_speed: int, pan: int, tilt: int,
                      model: Model = EVI_D31) -> bytes:
    """Pan-tiltDrive RelativePosition (8x 01 06 03 ...): move by (pan, tilt) units."""
    return _position_command(0x03, address, pan_speed, tilt_speed, pan, tilt, model)


def home(address: int) -> bytes:
    return bytes((_header(address), 0x01, 0x06, 0x04, TERMINATOR))


def reset(address: int) -> bytes:
    return bytes((_header(address), 0x01, 0x06, 0x05, TERMINATOR))


def position_inquiry(address: int) -> bytes:
    """Pan-tiltPosInq (8x 09 06 12 FF)."""
    return bytes((_header(address), 0x09, 0x06, 0x12, TERMINATOR))


def version_inquiry(address: int) -> bytes:
    """CAM_VersionInq (8x 09 00 02 FF): vendor, model, ROM revision, sockets."""
    return bytes((_header(address), 0x09, 0x00, 0x02, TERMINATOR))


@dataclass(frozen=True)
class Command:
    """A controller packet as the camera reads it. `address` 8 means broadcast."""
    kind: str        # address_set, if_clear, cancel, drive, absolute, relative, home, reset,
    #                  position_inquiry, version_inquiry
    address: int
    socket: int = 0                          # cancel
    direction: Direction | None = None       # drive
    pan_speed: int = 0
    tilt_speed: int = 0
    pan: int = 0                             # absolute / relative, camera units
    tilt: int = 0

    @property
    def is_inquiry(self) -> bool:
        return self.kind.endswith("_inquiry")

    @property
    def moves(self) -> bool:
        """Whether it is a pan-tilt motion command."""
        return self.kind in ("drive", "absolute", "relative", "home", "reset")


def decode_command(packet: bytes, model: Model = EVI_D31) -> Command:
    """Read one whole controller packet; ProtocolError (the camera's syntax error) if it is none
    that this camera knows, or a parameter is out of the model's range."""
    _check_frame(packet)
    head, body = packet[0], bytes(packet[1:-1])
    if not 0x81 <= head <= 0x88:
        raise ProtocolError(f"byte 0: header {head:#04x} is not a controller header (81..88)")
    address = head & 0x0F
    if head == BROADCAST:
        if body == b"\x30\x01":
            return Command("address_set", address)
        if body == b"\x01\x00\x01":
            return Command("if_clear", address)
        raise ProtocolError(f"byte 1: broadcast {body.hex(' ')} is neither AddressSet nor IF_Clear")
    if len(body) == 1 and body[0] >> 4 == 0x2:
        return Command("cancel", address, socket=body[0] & 0x0F)
    if body == b"\x01\x00\x01":
        return Command("if_clear", address)
    if body == b"\x09\x06\x12":
        return Command("position_inquiry", address)
    if body == b"\x09\x00\x02":
        return Command("version_inquiry", address)
    if body[:2] == b"\x01\x06" and len(body) >= 3:
        return _decode_pan_tilt(address, body, model)
    raise ProtocolError(f"byte 1: {body.hex(' ')} is not a command this camera knows")


def _decode_pan_tilt(address: int, body: bytes, model: Model) -> Command:
    code = body[2]
    if code in (0x04, 0x05) and len(body) == 3:
        return Command("home" if code == 0x04 else "reset", address)
    if code == 0x01 and len(body) == 7:
        pan_speed, tilt_speed = _speeds(body, model)
        try:
            direction = Direction((body[5], body[6]))
        except ValueError:
            raise ProtocolError(f"byte 6: direction {body[5]:02x} {body[6]:02x} is none of "
                                f"Pan-tiltDrive's (01..03 each)") from None
        return Command("drive", address, direction=direction, pan_speed=pan_speed,
                       tilt_speed=tilt_speed)
    if code in (0x02, 0x03) and len(body) == 13:
        pan_speed, tilt_speed = _speeds(body, model)
        pan, tilt = from_nibbles(body[5:9]), from_nibbles(body[9:13])
        kind = "absolute" if code == 0x02 else "relative"
        if kind == "absolute":
            for offset, axis, value, (low, high) in ((6, "pan", pan, model.pan_range),
                                                     (10, "tilt", tilt, model.tilt_range)):
                if not low <= value <= high:
                    raise ProtocolError(f"byte {offset}: {axis} position {value} outside "
                                        f"{model.name}'s {low}..{high}")
        return Command(kind, address, pan_speed=pan_speed, tilt_speed=tilt_speed, pan=pan,
                       tilt=tilt)
    raise ProtocolError(f"byte 3: pan-tilt command {code:02x} with {len(body) - 3} parameter "
                        f"bytes is not one this camera knows")


def _speeds(body: bytes, model: Model) -> tuple[int, int]:
    pan_speed, tilt_speed = body[3], body[4]
    if not 1 <= pan_speed <= model.max_pan_speed:
        raise ProtocolError(f"byte 4: pan speed {pan_speed:#04x} outside 01..{model.max_pan_speed:02x}")
    if not 1 <= tilt_speed <= model.max_tilt_speed:
        raise ProtocolError(f"byte 5: tilt speed {tilt_speed:#04x} outside "
                            f"01..{model.max_tilt_speed:02x}")
    return pan_speed, tilt_speed


# -- camera to controller ---------------------------------------------------------------------------
def _reply_header(address: int) -> int:
    if address not in ADDRESSES:
        raise CommandError(f"VISCA address {address}: allowed 1..7")
    return (address + 8) << 4


def ack(address: int, socket: int) -> bytes:
    return bytes((_reply_header(address), 0x40 | socket, TERMINATOR))


def completion(address: int, socket: int) -> bytes:
    return bytes((_reply_header(address), 0x50 | socket, TERMINATOR))


def error(address: int, socket: int, code: ErrorCode) -> bytes:
    return bytes((_reply_header(address), 0x60 | socket, int(code), TERMINATOR))


def position_reply(address: int, pan: int, tilt: int) -> bytes:
    """Pan-tiltPosInq's answer: y0 50 0w0w0w0w 0z0z0z0z FF."""
    return (bytes((_reply_header(address), 0x50)) + nibbles(pan) + nibbles(tilt)
            + bytes((TERMINATOR,)))


def version_reply(address: int, model: Model, rom: int = 0x0100, sockets: int = 2) -> bytes:
    """CAM_VersionInq's answer: y0 50 GG GG HH HH JJ JJ KK FF."""
    return bytes((_reply_header(address), 0x50, *model.vendor_id.to_bytes(2, "big"),
                  *model.model_id.to_bytes(2, "big"), *rom.to_bytes(2, "big"), sockets,
                  TERMINATOR))


def address_set_reply(next_address: int) -> bytes:
    """What the last camera on the chain sends back: 88 30 0w FF (w = the next free address)."""
    return bytes((BROADCAST, 0x30, next_address, TERMINATOR))


@dataclass(frozen=True)
class Reply:
    """A camera packet. kind: ack, completion, error, answer (an inquiry's data),
    address_set, if_clear (the broadcast IF_Clear coming back), network_change."""
    kind: str
    address: int = 0
    socket: int = 0
    code: int = 0                        # error
    data: bytes = field(default=b"")     # answer

    @property
    def error_name(self) -> str:
        return ERROR_NAMES.get(self.code, f"error {self.code:#04x}")  # type: ignore[call-overload]


def decode_reply(packet: bytes) -> Reply:
    """Read one whole camera packet; ProtocolError with the byte and the reason if it is none."""
    _check_frame(packet)
    head, body = packet[0], bytes(packet[1:-1])
    if head == BROADCAST:
        if len(body) == 2 and body[0] == 0x30:
            return Reply("address_set", socket=0, data=body[1:])
        if body == b"\x01\x00\x01":
            return Reply("if_clear")
        raise ProtocolError(f"byte 1: broadcast {body.hex(' ')} is no reply")
    if head & 0x0F or not 0x90 <= head <= 0xF0:
        raise ProtocolError(f"byte 0: header {head:#04x} is not a camera header (90..F0)")
    address = (head >> 4) - 8
    kind, socket = body[0] >> 4, body[0] & 0x0F
    if body == b"\x38":
        return Reply("network_change", address)
    if kind == 0x4 and len(body) == 1:
        return Reply("ack", address, socket)
    if kind == 0x5 and len(body) == 1:
        return Reply("completion", address, socket)
    if kind == 0x5 and socket == 0:
        return Reply("answer", address, 0, data=body[1:])
    if kind == 0x6 and len(body) == 2:
        return Reply("error", address, socket, code=body[1])
    raise ProtocolError(f"byte 1: {body.hex(' ')} is no ACK (4y), completion or answer (5y), "
                        f"or error (6y EE)")


def decode_position(reply: Reply) -> tuple[int, int]:
    """(pan, tilt) units from Pan-tiltPosInq's answer."""
    if reply.kind != "answer" or len(reply.data) != 8:
        raise ProtocolError(f"position answer: expected 8 data bytes, got {reply.kind} with "
                            f"{len(reply.data)}")
    return from_nibbles(reply.data[:4]), from_nibbles(reply.data[4:])


def decode_version(reply: Reply) -> tuple[int, int, int, int]:
    """(vendor, model, ROM revision, sockets) from CAM_VersionInq's answer."""
    data = reply.data
    if reply.kind != "answer" or len(data) != 7:
        raise ProtocolError(f"version answer: expected 7 data bytes, got {reply.kind} with "
                            f"{len(data)}")
    return (int.from_bytes(data[0:2], "big"), int.from_bytes(data[2:4], "big"),
            int.from_bytes(data[4:6], "big"), data[6])


def _check_frame(packet: bytes) -> None:
    if not MIN_PACKET <= len(packet) <= MAX_PACKET:
        raise ProtocolError(f"packet of {len(packet)} bytes: allowed {MIN_PACKET}..{MAX_PACKET}")
    if packet[-1] != TERMINATOR:
        raise ProtocolError(f"byte {len(packet) - 1}: {packet[-1]:#04x} where the terminator FF "
                            f"belongs")
    if TERMINATOR in packet[:-1]:
        raise ProtocolError(f"byte {packet.index(TERMINATOR)}: a terminator FF inside the packet")


# -- the byte stream --------------------------------------------------------------------------------
class ViscaParser(FramedParser):
    """Splits a byte stream into packets: a header byte (80..FE) up to the next FF, at most 16
    bytes. Bytes outside any packet, and a header with no FF within 16 bytes, are dropped and
    counted with their offset (robots.link.parser's guarantees)."""

    max_frame = MAX_PACKET

    def frame_length(self, buf: bytearray, start: int) -> int | None:
        end = buf.find(TERMINATOR, start + 1, start + MAX_PACKET)
        if end >= 0:
            if end - start + 1 < MIN_PACKET:
                raise Reject("length", f"packet of {end - start + 1} bytes: allowed "
                                       f"{MIN_PACKET}..{MAX_PACKET}")
            return end - start + 1
        if len(buf) - start >= MAX_PACKET:
            raise Reject("length", f"no terminator FF within {MAX_PACKET} bytes of the header")
        return None

    def decode(self, frame: bytes) -> bytes:
        return frame

    def _scan(self, packets: list) -> int:
        buf, pos, after_reject = self._buf, 0, -1
        while True:
            start = _next_header(buf, pos)
            if start < 0:
                self._stray(pos, len(buf), pos == after_reject)
                return len(buf)
            self._stray(pos, start, pos == after_reject)
            pos = start
            try:
                length = self.frame_length(buf, pos)
            except Reject as exc:
                pos = after_reject = self._reject(exc, pos)
                continue
            if length is None:
                return pos
            packets.append(self.decode(bytes(buf[pos:pos + length])))
            self.stats.packets += 1
            pos += length

    def _stray(self, start: int, end: int, after_reject: bool) -> None:
        if end <= start:
            return
        what = f"{end - start} byte(s) outside any packet (no header 80..FE before them)"
        if after_reject:                 # keep the rejection's reason, which explains these
            self.stats.last_error += f"; then {what}"
        else:
            self.stats.last_error = f"byte {self._base + start}: {what}"
        self._count_drop(end - start)


def _next_header(buf: bytearray, pos: int) -> int:
    for i in range(pos, len(buf)):
        if 0x80 <= buf[i] < TERMINATOR:
            return i
    return -1
