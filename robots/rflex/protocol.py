"""The rFLEX wire protocol (RWI / iRobot B21r), pure: bytes in, values out, no I/O.

See `shared/protocols/rflex.md`. A frame is `1B 02 | port id opcode dlen | data | crc | 1B 03`,
multi-byte fields big-endian, crc the XOR of port, id, opcode, dlen and the data.

Two asymmetries follow the notes:
- **Receive** (host side, and the emulator reading commands): `1B 00` inside a frame is one data
  byte 0x1B and `1B 01` is dropped, as the ROS reader does.
- **Transmit to the controller**: nothing shows that the controller unescapes, so a command never
  contains 0x1B between start and end. A field that would is moved to the nearest clean value
  (`clean_value`; at most 128 units for values below 2**16, ±1 unit for a low byte) and a
  checksum that would be 0x1B is avoided by a ±1-unit change of one designated field
  (`NUDGE_BOUND`). The emulator, playing the controller, escapes its reports with `1B 00`.
"""
from __future__ import annotations

import math
import struct
from dataclasses import dataclass

from robots.exceptions import CommandError, ProtocolError
from robots.link.parser import FramedParser, Reject

ESC, STX, ETX = 0x1B, 0x02, 0x03
ESC_DATA, ESC_SKIP = 0x00, 0x01
START = bytes((ESC, STX))
END = bytes((ESC, ETX))

# Ports (the first header byte).
SYS, MOT, JSTK, SONAR, DIO, IR = 1, 2, 3, 4, 5, 6

# Opcodes per port.
SYS_LCD_DUMP, SYS_STATUS = 0, 1
MOT_AXIS_SET_DIR, MOT_AXIS_SET_POS = 7, 8
MOT_SET_DEFAULTS, MOT_BRAKE_SET, MOT_BRAKE_RELEASE = 10, 11, 12
MOT_SYSTEM_REPORT, MOT_SYSTEM_REPORT_REQ = 33, 34
JSTK_GET_STATE = 0
SONAR_RUN, SONAR_REPORT = 0, 2
DIO_REPORTS_REQ, DIO_REPORT, DIO_SET = 0, 1, 4
IR_RUN, IR_REPORT = 0, 1

TRANSLATION_AXIS, ROTATION_AXIS = 0, 1
SONAR_ID = 4                 # Player sends id 4 with sonar commands, 0 otherwise
REPORT_PERIOD_US = 100_000   # 10 Hz; the drivers say "ms", 0.1 s in µs is the only sane reading
TRANSLATION_TORQUE = 30_000  # Player / ROS
ROTATION_TORQUE = 35_000
ROTATION_ACCEL = 100_000     # units/s², fixed in Player and ROS

# Header, crc and the two delimiters; the body (port..crc) is dlen + 5 bytes.
FRAME_OVERHEAD = 9
MAX_BODY = 255 + 5
U32_MAX = 2**32 - 1
NUDGE_BOUND = 4              # units a field may move to keep the checksum clean

# B21r constants (rflex.md §6).
SONAR_RAW_PER_M = 1476.0
SONAR_NO_ECHO = 32766        # CARMEN's "no echo"
SONAR_COUNT = 48
BUMPER_FIRST_ADDRESS = 0x40  # 14 panels at 0x40..0x4D
BUMPER_PANELS = 14
HOME_ADDRESS = 0x31          # heading-home event
VOLTS_OFFSET = 1.2


def _sonar_wire_ids() -> tuple[int, ...]:
    """Profile index -> wire id (board * 16 + index): boards 0-5 hold 4 each (the enclosure
    ring, indices 0-23), boards 6-13 hold 3 each (the base ring, indices 24-47)."""
    enclosure = [board * 16 + i for board in range(6) for i in range(4)]
    base = [board * 16 + i for board in range(6, 14) for i in range(3)]
    return tuple(enclosure + base)


SONAR_WIRE_IDS = _sonar_wire_ids()
SONAR_INDEX_OF_WIRE_ID = {wire: index for index, wire in enumerate(SONAR_WIRE_IDS)}


# --------------------------------------------------------------------------- frames

@dataclass(frozen=True)
class Frame:
    """One unescaped frame; `data` holds exactly dlen bytes."""
    port: int
    opcode: int
    data: bytes = b""
    id: int = 0


def xor_bytes(data: bytes) -> int:
    """XOR of all bytes, folded as one big integer (a handful of big-int operations instead
    of one Python step per byte)."""
    width = len(data)
    value = int.from_bytes(data, "little")
    while width > 1:
        half = (width + 1) // 2
        value = (value & ((1 << (8 * half)) - 1)) ^ (value >> (8 * half))
        width = half
    return value


def checksum(port: int, id_: int, opcode: int, data: bytes) -> int:
    """XOR of port, id, opcode, dlen and every data byte."""
    return port ^ id_ ^ opcode ^ len(data) ^ xor_bytes(data)


def frame_body(frame: Frame) -> bytes:
    """port id opcode dlen data crc, unescaped."""
    if len(frame.data) > 255:
        raise CommandError(f"frame data is {len(frame.data)} bytes; allowed 0 .. 255")
    crc = checksum(frame.port, frame.id, frame.opcode, frame.data)
    return bytes((frame.port, frame.id, frame.opcode, len(frame.data))) + frame.data + bytes((crc,))


def encode_raw(frame: Frame) -> bytes:
    """A command frame as sent to the controller: refuses any 0x1B between start and end."""
    body = frame_body(frame)
    where = body.find(ESC)
    if where >= 0:
        raise CommandError(
            f"port {frame.port} opcode {frame.opcode}: byte {where + 2} of the frame would be 0x1B, "
            "which the controller may read as a delimiter; build the command with a clean encoder")
    return START + body + END


def escape(body: bytes) -> bytes:
    """Stuff every 0x1B as `1B 00` (the controller-to-host direction)."""
    return body.replace(b"\x1b", b"\x1b\x00")


def encode_escaped(frame: Frame) -> bytes:
    """A report frame as the controller sends it: body escaped with `1B 00`."""
    return START + escape(frame_body(frame)) + END


# --------------------------------------------------------------------------- clean values

def has_escape_byte(value: int, size: int = 4) -> bool:
    return ESC in value.to_bytes(size, "big")


def clean_value(value: int, size: int = 4) -> int:
    """The unsigned value nearest to `value` whose big-endian bytes hold no 0x1B.

    For the highest offending byte k the candidates are that byte at 0x1A with 0xFF below, or
    at 0x1C with 0x00 below; the change is at most 2**(8k) / 2 (128 units when k = 1, 1 unit
    when k = 0). Ties go down (towards less speed).
    """
    limit = 2 ** (8 * size) - 1
    if not 0 <= value <= limit:
        raise CommandError(f"value {value} outside 0 .. {limit}")
    raw = value.to_bytes(size, "big")
    if ESC not in raw:
        return value
    k = size - 1 - raw.index(ESC)       # highest offending byte, counted from the low end
    unit = 256 ** k
    block = value - value % unit - ESC * unit  # the value with byte k and below zeroed
    below = block + 0x1A * unit + (unit - 1)
    above = block + 0x1C * unit
    candidates = [c for c in (below, above) if 0 <= c <= limit and not has_escape_byte(c, size)]
    return min(candidates, key=lambda c: (abs(c - value), c))


def max_clean_shift(value: int, size: int = 4) -> int:
    """Upper bound of |clean_value(value) - value|, from the highest byte that is 0x1B."""
    raw = value.to_bytes(size, "big")
    if ESC not in raw:
        return 0
    k = size - 1 - raw.index(ESC)
    return max(1, 256 ** k // 2)


# --------------------------------------------------------------------------- command encoders

@dataclass(frozen=True)
class Field:
    """One data field of a command: name (for errors), value, struct code (B, H, I)."""
    name: str
    value: int
    code: str


_SIZES = {"B": 1, "H": 2, "I": 4}


def _check_range(command: str, field: Field) -> None:
    limit = 2 ** (8 * _SIZES[field.code]) - 1
    if isinstance(field.value, bool) or not isinstance(field.value, int) or not 0 <= field.value <= limit:
        raise CommandError(f"{command}: {field.name} = {field.value!r}; allowed 0 .. {limit}")


def _pack(fields: list[Field]) -> bytes:
    return b"".join(struct.pack(">" + f.code, f.value) for f in fields)


def clean_command(command: str, port: int, opcode: int, fields: list[Field],
                  nudge: str | None = None, id_: int = 0) -> Frame:
    """Build a command whose frame holds no 0x1B between start and end.

    Multi-byte fields move to their nearest clean value; a one-byte field that is 0x1B has no
    nearby meaning and is refused. If the checksum comes out 0x1B, the field named `nudge`
    moves by the smallest amount (±1, ±2, ... up to NUDGE_BOUND units) that makes it clean.
    """
    cleaned = []
    for field in fields:
        _check_range(command, field)
        if field.code == "B":
            if field.value == ESC:
                raise CommandError(f"{command}: {field.name} = 0x1B cannot be sent; allowed any other byte")
            cleaned.append(field)
        else:
            cleaned.append(Field(field.name, clean_value(field.value, _SIZES[field.code]), field.code))
    frame = Frame(port, opcode, _pack(cleaned), id_)
    if checksum(port, id_, opcode, frame.data) != ESC:
        return frame
    if nudge is None:
        raise CommandError(f"{command}: checksum would be 0x1B and no field may move")
    index = next(i for i, f in enumerate(cleaned) if f.name == nudge)
    target = cleaned[index]
    limit = 2 ** (8 * _SIZES[target.code]) - 1
    for step in range(1, NUDGE_BOUND + 1):
        for delta in (step, -step):
            value = target.value + delta
            if not 0 <= value <= limit or has_escape_byte(value, _SIZES[target.code]):
                continue
            trial = cleaned[:index] + [Field(target.name, value, target.code)] + cleaned[index + 1:]
            data = _pack(trial)
            if checksum(port, id_, opcode, data) != ESC:
                return Frame(port, opcode, data, id_)
    raise CommandError(f"{command}: no clean checksum within {NUDGE_BOUND} units of {nudge}")


def brake_release() -> Frame:
    return Frame(MOT, MOT_BRAKE_RELEASE)


def brake_set() -> Frame:
    return Frame(MOT, MOT_BRAKE_SET)


def set_defaults() -> Frame:
    return Frame(MOT, MOT_SET_DEFAULTS)


def system_status_request() -> Frame:
    return Frame(SYS, SYS_STATUS)


def joystick_request() -> Frame:
    return Frame(JSTK, JSTK_GET_STATE)


_SET_DIR = struct.Struct(">BIIIB")


def axis_set_dir(axis: int, velocity: int, accel: int, torque: int) -> Frame:
    """Drive one axis: `velocity` is signed (units/s); the frame holds |velocity| and a direction
    byte (1 when velocity >= 0). A checksum fix moves the acceleration, never the velocity, so
    a zero command stays exactly zero.

    Sent twice a tick: plain ints whose packed bytes and checksum hold no 0x1B (nearly every
    command) are packed in one go, which is what `clean_command` would return for them; the
    rest, and anything to refuse, take `clean_command`'s way."""
    if (type(axis) is int and type(velocity) is int and type(accel) is int
            and type(torque) is int and 0 <= axis <= 0xFF and -U32_MAX <= velocity <= U32_MAX
            and 0 <= accel <= U32_MAX and 0 <= torque <= U32_MAX):
        data = _SET_DIR.pack(axis, abs(velocity), accel, torque, 1 if velocity >= 0 else 0)
        if ESC not in data and checksum(MOT, 0, MOT_AXIS_SET_DIR, data) != ESC:
            return Frame(MOT, MOT_AXIS_SET_DIR, data)
    return clean_command(
        "MOT_AXIS_SET_DIR", MOT, MOT_AXIS_SET_DIR,
        [Field("axis", axis, "B"), Field("velocity", abs(velocity), "I"),
         Field("acceleration", accel, "I"), Field("torque", torque, "I"),
         Field("direction", 1 if velocity >= 0 else 0, "B")],
        nudge="acceleration")


def axis_set_pos(axis: int, velocity: int, accel: int, torque: int, position: int) -> Frame:
    return clean_command(
        "MOT_AXIS_SET_POS", MOT, MOT_AXIS_SET_POS,
        [Field("axis", axis, "B"), Field("velocity", velocity, "I"), Field("acceleration", accel, "I"),
         Field("torque", torque, "I"), Field("position", position & U32_MAX, "I")],
        nudge="acceleration")


def system_report_request(period_us: int, axis_mask: int) -> Frame:
    """Motor/odometry reports every `period_us` for the axes in `axis_mask` (0, 0 = off)."""
    return clean_command("MOT_SYSTEM_REPORT_REQ", MOT, MOT_SYSTEM_REPORT_REQ,
                         [Field("period", period_us, "I"), Field("axis mask", axis_mask, "I")],
                         nudge="period" if period_us else None)


def sonar_run(on: bool, echo_delay: int = 30_000, ping_delay: int = 0, set_delay: int = 0) -> Frame:
    return clean_command("SONAR_RUN", SONAR, SONAR_RUN,
                         [Field("echo delay", echo_delay, "I"), Field("ping delay", ping_delay, "I"),
                          Field("set delay", set_delay, "I"), Field("mode", 2 if on else 0, "B")],
                         nudge="echo delay", id_=SONAR_ID)


def dio_reports_request(period_us: int) -> Frame:
    return clean_command("DIO_REPORTS_REQ", DIO, DIO_REPORTS_REQ, [Field("period", period_us, "I")],
                         nudge="period" if period_us else None)


def dio_set(net_id: int, offset: int, state: int, mask: int) -> Frame:
    return clean_command("DIO_SET", DIO, DIO_SET,
                         [Field("net id", net_id, "B"), Field("offset", offset, "B"),
                          Field("state", state, "B"), Field("mask", mask, "B")])


def ir_run(on: bool) -> Frame:
    values = (0, 70, 10, 20, 150)
    return clean_command("IR_RUN", IR, IR_RUN,
                         [Field(f"parameter {i}", v, "I") for i, v in enumerate(values)]
                         + [Field("mode", 2 if on else 0, "B")], nudge="parameter 0")


def velocity_units(value: float, conv: float) -> int:
    """SI value (m/s, rad/s, m/s²) to controller units, rounded; NaN or inf is refused."""
    if not math.isfinite(value):
        raise CommandError(f"velocity {value!r} is not finite; allowed any finite number")
    units = round(value * conv)
    if abs(units) > U32_MAX:
        raise CommandError(f"velocity {value} ({units} units) outside ±{U32_MAX} units")
    return units


# --------------------------------------------------------------------------- decoded commands

@dataclass(frozen=True)
class SetDir:
    axis: int
    velocity: int      # signed: direction applied
    accel: int
    torque: int


@dataclass(frozen=True)
class SetPos:
    axis: int
    velocity: int
    accel: int
    torque: int
    position: int


@dataclass(frozen=True)
class ReportRequest:
    period_us: int
    axis_mask: int


@dataclass(frozen=True)
class SonarRun:
    on: bool


@dataclass(frozen=True)
class DioRequest:
    period_us: int


@dataclass(frozen=True)
class Simple:
    """A command without data (brake, defaults, status, joystick)."""
    port: int
    opcode: int


def _need(frame: Frame, size: int, what: str) -> None:
    if len(frame.data) != size:
        raise ProtocolError(f"{what}: dlen {len(frame.data)}, expected {size}")


def decode_command(frame: Frame):
    """Controller side: what the host asked for. Unknown commands raise ProtocolError."""
    key = (frame.port, frame.opcode)
    if key == (MOT, MOT_AXIS_SET_DIR):
        _need(frame, 14, "MOT_AXIS_SET_DIR")
        axis, velocity, accel, torque, direction = struct.unpack(">BIIIB", frame.data)
        return SetDir(axis, velocity if direction else -velocity, accel, torque)
    if key == (MOT, MOT_AXIS_SET_POS):
        _need(frame, 17, "MOT_AXIS_SET_POS")
        return SetPos(*struct.unpack(">BIIIi", frame.data))
    if key == (MOT, MOT_SYSTEM_REPORT_REQ):
        _need(frame, 8, "MOT_SYSTEM_REPORT_REQ")
        return ReportRequest(*struct.unpack(">II", frame.data))
    if key == (SONAR, SONAR_RUN):
        _need(frame, 13, "SONAR_RUN")
        return SonarRun(frame.data[12] == 2)
    if key == (DIO, DIO_REPORTS_REQ):
        _need(frame, 4, "DIO_REPORTS_REQ")
        return DioRequest(*struct.unpack(">I", frame.data))
    if key in ((MOT, MOT_SET_DEFAULTS), (MOT, MOT_BRAKE_SET), (MOT, MOT_BRAKE_RELEASE),
               (SYS, SYS_STATUS), (JSTK, JSTK_GET_STATE)):
        return Simple(*key)
    if key in ((IR, IR_RUN), (DIO, DIO_SET), (SYS, SYS_LCD_DUMP)):
        return Simple(*key)
    raise ProtocolError(f"unknown command port {frame.port} opcode {frame.opcode}")


# --------------------------------------------------------------------------- reports

@dataclass(frozen=True)
class MotorReport:
    rv: int
    timestamp: int
    axis: int
    position: int      # signed 32-bit counter; differences wrap
    velocity: int
    accel: int
    torque: int


@dataclass(frozen=True)
class SonarReport:
    rv: int
    timestamp: int
    readings: tuple[tuple[int, int], ...]   # (wire id, raw range)


@dataclass(frozen=True)
class DioReport:
    timestamp: int
    address: int
    data: int


@dataclass(frozen=True)
class JoystickReport:
    timestamp: int
    x: int
    y: int
    buttons: int


@dataclass(frozen=True)
class SystemStatus:
    timestamp: int
    voltage: int
    brake: int

    @property
    def volts(self) -> float:
        return self.voltage / 100.0 + VOLTS_OFFSET


MOTOR_REPORT = struct.Struct(">IIBiiii")
DIO_FORMAT = struct.Struct(">IBH")
JOYSTICK_FORMAT = struct.Struct(">IiiB")
STATUS_FORMAT = struct.Struct(">IIB")
SONAR_READING = struct.Struct(">BH")


def decode_report(frame: Frame):
    """Host side: a typed report, or ProtocolError naming the frame and the reason."""
    key = (frame.port, frame.opcode)
    if key == (MOT, MOT_SYSTEM_REPORT):
        _need(frame, MOTOR_REPORT.size, "MOT_SYSTEM_REPORT")
        return MotorReport(*MOTOR_REPORT.unpack(frame.data))
    if key == (SONAR, SONAR_REPORT):
        return _decode_sonar(frame.data)
    if key == (DIO, DIO_REPORT):
        _need(frame, DIO_FORMAT.size, "DIO_REPORT")
        return DioReport(*DIO_FORMAT.unpack(frame.data))
    if key == (JSTK, JSTK_GET_STATE):
        _need(frame, JOYSTICK_FORMAT.size, "joystick report")
        return JoystickReport(*JOYSTICK_FORMAT.unpack(frame.data))
    if key == (SYS, SYS_STATUS):
        _need(frame, STATUS_FORMAT.size, "SYS_STATUS reply")
        return SystemStatus(*STATUS_FORMAT.unpack(frame.data))
    raise ProtocolError(f"unknown report port {frame.port} opcode {frame.opcode}")


def _decode_sonar(data: bytes) -> SonarReport:
    if len(data) < 8 or (len(data) - 8) % 3:
        raise ProtocolError(f"SONAR_REPORT: dlen {len(data)} is not 8 + 3n")
    rv, timestamp = struct.unpack_from(">II", data)
    readings = tuple(SONAR_READING.iter_unpack(data[8:]))
    return SonarReport(rv, timestamp, readings)


def motor_report(seq: int, report: MotorReport) -> Frame:
    return Frame(MOT, MOT_SYSTEM_REPORT, MOTOR_REPORT.pack(
        report.rv, report.timestamp, report.axis, report.position, report.velocity,
        report.accel, report.torque), seq & 0xFF)


def sonar_report(seq: int, report: SonarReport) -> Frame:
    data = struct.pack(">II", report.rv, report.timestamp) + b"".join(
        struct.pack(">BH", wire, raw) for wire, raw in report.readings)
    return Frame(SONAR, SONAR_REPORT, data, seq & 0xFF)


_SONAR_WIRE_ID_BYTES = bytes(SONAR_WIRE_IDS)


def sonar_report_of_raws(seq: int, rv: int, timestamp: int, raws: list[int]) -> Frame:
    """`sonar_report` for the first len(raws) sonars of the ring in profile order (wire ids
    SONAR_WIRE_IDS), the raw ranges 0 .. 65535: the same bytes, laid out in three slice
    assignments instead of a pack per reading (the emulator sends 48 of them ten times a second)."""
    n = len(raws)
    if n > SONAR_COUNT:
        raise CommandError(f"{n} sonar readings; the ring has {SONAR_COUNT}")
    data = bytearray(8 + 3 * n)
    struct.pack_into(">II", data, 0, rv, timestamp)
    ranges = struct.pack(f">{n}H", *raws)
    data[8::3] = _SONAR_WIRE_ID_BYTES[:n]
    data[9::3] = ranges[0::2]
    data[10::3] = ranges[1::2]
    return Frame(SONAR, SONAR_REPORT, bytes(data), seq & 0xFF)


def dio_report(seq: int, report: DioReport) -> Frame:
    return Frame(DIO, DIO_REPORT, DIO_FORMAT.pack(report.timestamp, report.address, report.data), seq & 0xFF)


def joystick_report(seq: int, report: JoystickReport) -> Frame:
    return Frame(JSTK, JSTK_GET_STATE, JOYSTICK_FORMAT.pack(report.timestamp, report.x, report.y,
                                                            report.buttons), seq & 0xFF)


def status_report(seq: int, report: SystemStatus) -> Frame:
    return Frame(SYS, SYS_STATUS, STATUS_FORMAT.pack(report.timestamp, report.voltage, report.brake), seq & 0xFF)


def wrap_delta(new: int, old: int) -> int:
    """Signed 32-bit difference of two counters (wraps at ±2**31)."""
    return (new - old + 2**31) % 2**32 - 2**31


def sonar_metres(raw: int) -> float:
    """Raw sonar range to metres; the no-echo value is infinity."""
    return math.inf if raw >= SONAR_NO_ECHO else raw / SONAR_RAW_PER_M


def sonar_raw(metres: float) -> int:
    """Metres to the raw range the controller sends (no echo for inf/NaN or beyond the scale)."""
    if not math.isfinite(metres) or metres < 0:
        return SONAR_NO_ECHO
    return min(SONAR_NO_ECHO, round(metres * SONAR_RAW_PER_M))


# --------------------------------------------------------------------------- byte-fed parser

MAX_ESCAPED_FRAME = 2 + 2 * MAX_BODY + 2   # every body byte stuffed


def unescape(raw_body: bytes) -> bytes:
    """Undo the receive-side escapes: `1B 01` vanishes, `1B 00` is one 0x1B. Only valid on a
    body where every 0x1B starts a pair (FrameParser.frame_length checks that first)."""
    return raw_body.replace(b"\x1b\x01", b"").replace(b"\x1b\x00", b"\x1b")


class FrameParser(FramedParser):
    """Turns a byte stream into frames on the shared parser base (bounded, resyncing, counted).

    A frame runs from `1B 02` to the first `1B 03`; on the way `1B 00` and `1B 01` are escapes,
    and any other byte after 0x1B (including a new `1B 02`) rejects the frame, after which the
    base hunts for the next start. The closed frame is unescaped and checked for dlen and crc.
    """

    header = START
    max_frame = MAX_ESCAPED_FRAME

    def frame_length(self, buf: bytearray, start: int) -> int | None:
        pos = start + 2
        limit = start + self.max_frame
        while True:
            esc = buf.find(ESC, pos, limit)
            if esc < 0:
                if len(buf) >= limit:
                    raise Reject("length", f"no end of frame within {self.max_frame} bytes")
                return None
            if esc + 1 >= len(buf):
                return None
            code = buf[esc + 1]
            if code == ETX:
                return esc + 2 - start
            if code not in (ESC_DATA, ESC_SKIP):
                what = "a new start" if code == STX else f"bad escape 1B {code:02X}"
                raise Reject("escape", f"{what} {esc - start} bytes into the frame")
            pos = esc + 2

    def decode(self, frame: bytes) -> Frame:
        body = unescape(frame[2:-2])
        if len(body) < 5 or body[3] != len(body) - 5:
            raise Reject("length", f"{len(body)}-byte body does not match dlen "
                         f"{body[3] if len(body) > 3 else '?'}")
        crc = xor_bytes(body[:-1])
        if crc != body[-1]:
            raise Reject("checksum", f"crc {body[-1]:02X}, computed {crc:02X}")
        return Frame(body[0], body[2], bytes(body[4:-1]), body[1])
