"""CANopen (CiA 301) and the CiA 402 drive profile, pure: frames in, values out, no I/O.

Only the services the differential-drive driver uses: NMT, SYNC, EMCY, heartbeat/boot-up,
expedited SDO, and the fixed PDO layout of ../shared/protocols/canopen-drive.md §5
(RPDO1 = controlword + target velocity, TPDO1 = statusword + velocity actual, TPDO2 =
position actual). A frame is `(cob_id, data)`; data are little-endian with no padding.

The `canopen` package does the SDO client/server and the object dictionary at run time; this
module is what both ends agree on, written out so that golden frames can pin it down.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass
from enum import Enum, IntEnum

from robots.exceptions import ProtocolError

# -- COB-IDs (predefined connection set) ------------------------------------------------------
NMT_ID = 0x000
SYNC_ID = 0x080
EMCY_BASE = 0x080
TPDO_BASE = (0x180, 0x280, 0x380, 0x480)
RPDO_BASE = (0x200, 0x300, 0x400, 0x500)
SDO_TX_BASE = 0x580          # server -> client (the drive answers)
SDO_RX_BASE = 0x600          # client -> server (the host asks)
HEARTBEAT_BASE = 0x700
HOST_NODE = 0x7F             # the host's own heartbeat node id


def check_node(node: int) -> int:
    if not 1 <= node <= 127:
        raise ProtocolError(f"CANopen node id {node} outside 1..127")
    return node


def tpdo_id(number: int, node: int) -> int:
    return TPDO_BASE[number - 1] + check_node(node)


def rpdo_id(number: int, node: int) -> int:
    return RPDO_BASE[number - 1] + check_node(node)


def emcy_id(node: int) -> int:
    return EMCY_BASE + check_node(node)


def heartbeat_id(node: int) -> int:
    return HEARTBEAT_BASE + check_node(node)


# -- NMT -------------------------------------------------------------------------------------
class Nmt(IntEnum):
    START = 0x01
    STOP = 0x02
    PRE_OPERATIONAL = 0x80
    RESET_NODE = 0x81
    RESET_COMMUNICATION = 0x82


class NodeState(IntEnum):
    """The state byte of a heartbeat (0 = boot-up)."""
    BOOT_UP = 0x00
    STOPPED = 0x04
    OPERATIONAL = 0x05
    PRE_OPERATIONAL = 0x7F


def nmt(command: Nmt, node: int = 0) -> tuple[int, bytes]:
    """An NMT command to `node` (0 = all nodes)."""
    if node:
        check_node(node)
    return NMT_ID, bytes((int(command), node))


def decode_nmt(data: bytes) -> tuple[Nmt, int]:
    if len(data) != 2:
        raise ProtocolError(f"NMT frame: {len(data)} bytes, expected 2 (command, node)")
    try:
        return Nmt(data[0]), data[1]
    except ValueError:
        raise ProtocolError(f"NMT frame: byte 0: unknown command {data[0]:#04x}") from None


def sync(counter: int | None = None) -> tuple[int, bytes]:
    """SYNC: empty, or with the optional 1-byte counter (1..240)."""
    return SYNC_ID, b"" if counter is None else bytes((counter,))


def heartbeat(node: int, state: NodeState) -> tuple[int, bytes]:
    return heartbeat_id(node), bytes((int(state),))


def decode_heartbeat(data: bytes) -> NodeState:
    """The state in a heartbeat or boot-up frame; bit 7 is node guarding's toggle and ignored."""
    if len(data) != 1:
        raise ProtocolError(f"heartbeat frame: {len(data)} bytes, expected 1")
    try:
        return NodeState(data[0] & 0x7F)
    except ValueError:
        raise ProtocolError(f"heartbeat frame: byte 0: unknown NMT state {data[0]:#04x}") from None


# -- EMCY --------------------------------------------------------------------------------------
EMCY_MEANINGS = {
    0x0000: "error reset or no error",
    0x1000: "generic error",
    0x2310: "over-current at the motor output",
    0x3210: "DC-link over-voltage",
    0x3220: "DC-link under-voltage",
    0x4210: "drive over-temperature",
    0x5000: "device hardware",
    0x7305: "incremental encoder fault",
    0x8110: "CAN overrun (frames lost)",
    0x8120: "CAN in error-passive mode",
    0x8130: "heartbeat or life-guard error (host heartbeat lost)",
    0x8140: "recovered from bus-off",
    0x8210: "PDO not processed due to length error",
    0x8220: "PDO length exceeded",
    0x8250: "RPDO timeout (deadline monitoring)",
    0x8611: "following error (wheel cannot follow the demand)",
}
EMCY_CLASSES = ((0xFF00, "vendor-specific error"), (0x8000, "monitoring"), (0x7000, "additional modules"),
                (0x6000, "device software"), (0x5000, "device hardware"), (0x4000, "temperature"),
                (0x3000, "voltage"), (0x2000, "current"), (0x1000, "generic error"))


def emcy_meaning(code: int) -> str:
    """What an EMCY error code means: the exact entry, else its CiA 301 class."""
    if code in EMCY_MEANINGS:
        return EMCY_MEANINGS[code]
    for base, name in EMCY_CLASSES:
        if code >= base:
            return f"{name} (code {code:#06x})"
    return f"unknown error code {code:#06x}"


@dataclass(frozen=True)
class Emcy:
    code: int
    register: int
    vendor: bytes = b"\0" * 5

    @property
    def meaning(self) -> str:
        return emcy_meaning(self.code)


def emcy(node: int, code: int, register: int, vendor: bytes = b"") -> tuple[int, bytes]:
    if len(vendor) > 5:
        raise ProtocolError(f"EMCY vendor data: {len(vendor)} bytes, at most 5")
    return emcy_id(node), struct.pack("<HB", code, register) + vendor.ljust(5, b"\0")


def decode_emcy(data: bytes) -> Emcy:
    if len(data) != 8:
        raise ProtocolError(f"EMCY frame: {len(data)} bytes, expected 8 (code u16, register u8, "
                            f"5 vendor bytes)")
    code, register = struct.unpack_from("<HB", data)
    return Emcy(code, register, bytes(data[3:8]))


# -- expedited SDO -------------------------------------------------------------------------------
SDO_UPLOAD_REQUEST = 0x40
SDO_DOWNLOAD_RESPONSE = 0x60
SDO_ABORT = 0x80
_SIZED_DOWNLOAD = {1: 0x2F, 2: 0x2B, 3: 0x27, 4: 0x23}      # ccs=1, expedited, size indicated
_UPLOAD_SIZES = {0x4F: 1, 0x4B: 2, 0x47: 3, 0x43: 4}
SDO_ABORT_MEANINGS = {
    0x05030000: "toggle bit not alternated",
    0x05040000: "SDO protocol timed out",
    0x05040001: "client/server command specifier not valid or unknown",
    0x06010000: "unsupported access to an object",
    0x06010001: "attempt to read a write-only object",
    0x06010002: "attempt to write a read-only object",
    0x06020000: "object does not exist in the object dictionary",
    0x06040041: "object cannot be mapped to the PDO",
    0x06040042: "the number and length of the objects to be mapped would exceed the PDO length",
    0x06040043: "general parameter incompatibility",
    0x06060000: "access failed due to a hardware error",
    0x06070010: "data type does not match, length of service parameter does not match",
    0x06090011: "sub-index does not exist",
    0x06090030: "invalid value for parameter (download only)",
    0x06090031: "value of parameter written too high",
    0x06090032: "value of parameter written too low",
    0x08000000: "general error",
    0x08000020: "data cannot be transferred or stored to the application",
    0x08000021: "data cannot be transferred or stored because of local control",
    0x08000022: "data cannot be transferred or stored in the present device state",
}


def abort_meaning(code: int) -> str:
    return SDO_ABORT_MEANINGS.get(code, f"abort code {code:#010x} (not in CiA 301's table)")


def sdo_download(node: int, index: int, sub: int, value: bytes) -> tuple[int, bytes]:
    """Expedited download (write) request of 1-4 bytes."""
    if len(value) not in _SIZED_DOWNLOAD:
        raise ProtocolError(f"expedited SDO write of {len(value)} bytes; 1..4 allowed")
    return (SDO_RX_BASE + check_node(node),
            struct.pack("<BHB", _SIZED_DOWNLOAD[len(value)], index, sub) + value.ljust(4, b"\0"))


def sdo_upload(node: int, index: int, sub: int) -> tuple[int, bytes]:
    """Upload (read) request."""
    return SDO_RX_BASE + check_node(node), struct.pack("<BHB", SDO_UPLOAD_REQUEST, index, sub) + b"\0" * 4


def sdo_download_response(node: int, index: int, sub: int) -> tuple[int, bytes]:
    return SDO_TX_BASE + check_node(node), struct.pack("<BHB", SDO_DOWNLOAD_RESPONSE, index, sub) + b"\0" * 4


def sdo_upload_response(node: int, index: int, sub: int, value: bytes) -> tuple[int, bytes]:
    command = {v: k for k, v in _UPLOAD_SIZES.items()}.get(len(value))
    if command is None:
        raise ProtocolError(f"expedited SDO upload of {len(value)} bytes; 1..4 allowed")
    return SDO_TX_BASE + check_node(node), struct.pack("<BHB", command, index, sub) + value.ljust(4, b"\0")


def sdo_abort(node: int, index: int, sub: int, code: int, *, from_server: bool = True) -> tuple[int, bytes]:
    base = SDO_TX_BASE if from_server else SDO_RX_BASE
    return base + check_node(node), struct.pack("<BHBI", SDO_ABORT, index, sub, code)


@dataclass(frozen=True)
class SdoReply:
    """A decoded SDO server frame: a write acknowledged, a value read, or an abort."""
    kind: str              # "written", "value", "abort"
    index: int
    sub: int
    value: bytes = b""
    abort_code: int = 0

    @property
    def meaning(self) -> str:
        return abort_meaning(self.abort_code) if self.kind == "abort" else ""


def decode_sdo_reply(data: bytes) -> SdoReply:
    if len(data) != 8:
        raise ProtocolError(f"SDO frame: {len(data)} bytes, expected 8")
    command, index, sub = struct.unpack_from("<BHB", data)
    if command == SDO_ABORT:
        return SdoReply("abort", index, sub, abort_code=struct.unpack_from("<I", data, 4)[0])
    if command == SDO_DOWNLOAD_RESPONSE:
        return SdoReply("written", index, sub)
    if command in _UPLOAD_SIZES:
        return SdoReply("value", index, sub, bytes(data[4:4 + _UPLOAD_SIZES[command]]))
    raise ProtocolError(f"SDO frame: byte 0: command {command:#04x} is not an expedited reply "
                        f"(0x43/0x47/0x4B/0x4F, 0x60 or 0x80)")


# -- PDO mapping and the fixed layout ------------------------------------------------------------
def mapping_entry(index: int, sub: int, bits: int) -> int:
    """A PDO mapping entry: (index << 16) | (sub << 8) | bit length."""
    return (index << 16) | (sub << 8) | bits


def split_mapping(entry: int) -> tuple[int, int, int]:
    return entry >> 16, (entry >> 8) & 0xFF, entry & 0xFF


CONTROLWORD, STATUSWORD = 0x6040, 0x6041
MODES_OF_OPERATION, MODES_DISPLAY = 0x6060, 0x6061
POSITION_ACTUAL, VELOCITY_DEMAND, VELOCITY_ACTUAL = 0x6064, 0x606B, 0x606C
MAX_PROFILE_VELOCITY = 0x607F
PROFILE_ACCELERATION, PROFILE_DECELERATION, QUICK_STOP_DECELERATION = 0x6083, 0x6084, 0x6085
TARGET_VELOCITY = 0x60FF
ABORT_CONNECTION_OPTION = 0x6007
QUICK_STOP_OPTION = 0x605A
SHUTDOWN_OPTION = 0x605B
DISABLE_OPERATION_OPTION = 0x605C
FAULT_REACTION_OPTION = 0x605E
POLARITY = 0x607E
SUPPORTED_DRIVE_MODES = 0x6502
IDENTITY = 0x1018
PRE_DEFINED_ERROR_FIELD = 0x1003
COB_ID_SYNC = 0x1005
COB_ID_EMCY = 0x1014
ERROR_CODE = 0x603F
ERROR_REGISTER = 0x1001
DEVICE_TYPE = 0x1000
CONSUMER_HEARTBEAT = 0x1016
PRODUCER_HEARTBEAT = 0x1017
PROFILE_VELOCITY_MODE = 3

RPDO1_MAP = (mapping_entry(CONTROLWORD, 0, 16), mapping_entry(TARGET_VELOCITY, 0, 32))
TPDO1_MAP = (mapping_entry(STATUSWORD, 0, 16), mapping_entry(VELOCITY_ACTUAL, 0, 32))
TPDO2_MAP = (mapping_entry(POSITION_ACTUAL, 0, 32),)
PDO_INVALID = 0x80000000
SYNC_EVERY = 1               # transmission type: each SYNC


def rpdo1(node: int, controlword: int, target_velocity: int) -> tuple[int, bytes]:
    """RPDO1: controlword u16 + target velocity i32 (6 bytes)."""
    _check_range("controlword", controlword, 0, 0xFFFF)
    _check_range("target velocity", target_velocity, -2**31, 2**31 - 1)
    return rpdo_id(1, node), struct.pack("<Hi", controlword, target_velocity)


def decode_rpdo1(data: bytes) -> tuple[int, int]:
    _check_length("RPDO1", data, 6)
    return struct.unpack("<Hi", data)


def tpdo1(node: int, statusword: int, velocity: int) -> tuple[int, bytes]:
    """TPDO1: statusword u16 + velocity actual i32 (6 bytes)."""
    return tpdo_id(1, node), struct.pack("<Hi", statusword, velocity)


def decode_tpdo1(data: bytes) -> tuple[int, int]:
    _check_length("TPDO1", data, 6)
    return struct.unpack("<Hi", data)


def tpdo2(node: int, position: int) -> tuple[int, bytes]:
    """TPDO2: position actual i32 (4 bytes)."""
    return tpdo_id(2, node), struct.pack("<i", position)


def decode_tpdo2(data: bytes) -> int:
    _check_length("TPDO2", data, 4)
    return struct.unpack("<i", data)[0]


def _check_length(what: str, data: bytes, n: int) -> None:
    if len(data) != n:
        raise ProtocolError(f"{what}: {len(data)} bytes, expected {n} (is the drive's PDO mapping "
                            f"the one in docs/canopen.md?)")


def _check_range(field: str, value: int, low: int, high: int) -> None:
    if not low <= value <= high:
        from robots.exceptions import CommandError
        raise CommandError(f"{field} = {value} outside {low} .. {high}")


# -- CiA 402 power state machine -----------------------------------------------------------------
class Cw(IntEnum):
    """Controlword commands."""
    DISABLE_VOLTAGE = 0x0000
    QUICK_STOP = 0x0002
    SHUTDOWN = 0x0006
    SWITCH_ON = 0x0007
    ENABLE_OPERATION = 0x000F
    FAULT_RESET = 0x0080
    HALT = 0x010F


class State402(Enum):
    NOT_READY = "not ready to switch on"
    SWITCH_ON_DISABLED = "switch on disabled"
    READY_TO_SWITCH_ON = "ready to switch on"
    SWITCHED_ON = "switched on"
    OPERATION_ENABLED = "operation enabled"
    QUICK_STOP_ACTIVE = "quick stop active"
    FAULT_REACTION_ACTIVE = "fault reaction active"
    FAULT = "fault"


_STATES = (  # (mask, value, state), most specific first
    (0x4F, 0x08, State402.FAULT),
    (0x4F, 0x0F, State402.FAULT_REACTION_ACTIVE),
    (0x4F, 0x40, State402.SWITCH_ON_DISABLED),
    (0x6F, 0x21, State402.READY_TO_SWITCH_ON),
    (0x6F, 0x23, State402.SWITCHED_ON),
    (0x6F, 0x27, State402.OPERATION_ENABLED),
    (0x6F, 0x07, State402.QUICK_STOP_ACTIVE),
    (0x4F, 0x00, State402.NOT_READY),
)
# The statusword bits that define each state (bit 4 voltage enabled and bit 9 remote added).
STATUS_BITS = {
    State402.NOT_READY: 0x0000, State402.SWITCH_ON_DISABLED: 0x0240,
    State402.READY_TO_SWITCH_ON: 0x0231, State402.SWITCHED_ON: 0x0233,
    State402.OPERATION_ENABLED: 0x0237, State402.QUICK_STOP_ACTIVE: 0x0217,
    State402.FAULT_REACTION_ACTIVE: 0x021F, State402.FAULT: 0x0218,
}
SW_FAULT = 0x0008
SW_WARNING = 0x0080
SW_TARGET_REACHED = 0x0400
SW_INTERNAL_LIMIT = 0x0800
SW_SPEED_ZERO = 0x1000


def state_of(statusword: int) -> State402 | None:
    """The CiA 402 state a statusword shows (None when it matches none of the table's patterns)."""
    for mask, value, state in _STATES:
        if statusword & mask == value:
            return state
    return None


# The command that leads from a state towards Operation Enabled, and the state it should reach.
ENABLE_STEPS = {
    State402.SWITCH_ON_DISABLED: (Cw.SHUTDOWN, State402.READY_TO_SWITCH_ON),
    State402.READY_TO_SWITCH_ON: (Cw.SWITCH_ON, State402.SWITCHED_ON),
    State402.SWITCHED_ON: (Cw.ENABLE_OPERATION, State402.OPERATION_ENABLED),
    State402.QUICK_STOP_ACTIVE: (Cw.DISABLE_VOLTAGE, State402.SWITCH_ON_DISABLED),
}


# -- SocketCAN error frames ----------------------------------------------------------------------
CAN_ERR_CRTL = 0x00000004
CAN_ERR_BUSOFF = 0x00000040
CAN_ERR_RESTARTED = 0x00000100
CAN_ERR_CRTL_RX_PASSIVE = 0x10
CAN_ERR_CRTL_TX_PASSIVE = 0x20
CAN_ERR_CRTL_ACTIVE = 0x40


def decode_error_frame(can_id: int, data: bytes) -> str | None:
    """The bus state an error frame reports ("bus-off", "error-passive", "error-active"), or None.

    SocketCAN's convention (linux/can/error.h): the class is in the id, details in data[1]."""
    if can_id & CAN_ERR_BUSOFF:
        return "bus-off"
    if can_id & CAN_ERR_CRTL and len(data) > 1:
        if data[1] & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE):
            return "error-passive"
        if data[1] & CAN_ERR_CRTL_ACTIVE:
            return "error-active"
    if can_id & CAN_ERR_RESTARTED:
        return "error-active"
    return None
