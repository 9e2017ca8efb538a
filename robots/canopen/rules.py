"""What a CiA 301 device checks before it accepts an SDO access or a PDO configuration, pure.

Why a module: `canopen`'s LocalNode answers SDO from its object dictionary, but takes any
sub-index of a plain variable or an array, accepts any PDO mapping and any transmission type.
A drive from a maker does not, and a reference master relies on the refusals. Each function
returns the SDO abort code a device answers with, or None when the access is fine; the emulator
raises it (`robots.canopen.emulator`).
"""
from __future__ import annotations

from canopen.objectdictionary import ODArray, ODRecord, ODVariable

NO_OBJECT = 0x06020000             # object does not exist in the object dictionary
NO_SUB_INDEX = 0x06090011          # sub-index does not exist
UNSUPPORTED_ACCESS = 0x06010000    # e.g. mapping a valid PDO
CANNOT_MAP = 0x06040041            # object cannot be mapped to the PDO
MAP_TOO_LONG = 0x06040042          # mapped objects exceed the PDO length
INVALID_VALUE = 0x06090030         # invalid value for parameter (download only)
PDO_BITS = 64


def sdo_target(od, index: int, sub: int) -> int | None:
    """NO_OBJECT / NO_SUB_INDEX where `index:sub` is not in `od`. An array's sub-indices are
    those it was built with (LocalNode would invent any other from the first one)."""
    obj = od.get(index)
    if obj is None:
        return NO_OBJECT
    if isinstance(obj, ODVariable):
        return None if sub == 0 else NO_SUB_INDEX
    if isinstance(obj, (ODArray, ODRecord)) and sub not in obj.subindices:
        return NO_SUB_INDEX
    return None


def mapping_entry(od, entry: int, receive: bool) -> int | None:
    """A mapping entry (index << 16 | sub << 8 | bits) for an RPDO (`receive`) or a TPDO: the
    object exists, may be mapped (`pdo_mappable`, as an EDS says), is written (RPDO) or read (TPDO), and has that many bits."""
    index, sub, bits = entry >> 16, (entry >> 8) & 0xFF, entry & 0xFF
    if sdo_target(od, index, sub) is not None:
        return CANNOT_MAP
    var = od.get_variable(index, sub)
    if not var.pdo_mappable or (receive and not var.writable) or (not receive and not var.readable):
        return CANNOT_MAP
    if len(var) != bits:
        return CANNOT_MAP
    return None


def mapping_length(entries: list[int]) -> int | None:
    """MAP_TOO_LONG when the entries' bits exceed one CAN frame (8 bytes)."""
    return MAP_TOO_LONG if sum(e & 0xFF for e in entries) > PDO_BITS else None


def transmission_type(kind: int, receive: bool) -> int | None:
    """0-240 synchronous, 254/255 event-driven; 241-251 are reserved. RTR-only TPDOs
    (252/253) are not offered by this drive, and make no sense for an RPDO."""
    if kind <= 240 or kind in (254, 255):
        return None
    return INVALID_VALUE


def pdo_cob_id_change(old: int, new: int) -> int | None:
    """A valid PDO's COB-ID may not change (set bit 31 first); bit 29 (extended ids) is not
    offered."""
    valid_before = not old & 0x80000000
    if new & 0x20000000:
        return INVALID_VALUE
    if valid_before and not new & 0x80000000 and (new & 0x7FF) != (old & 0x7FF):
        return INVALID_VALUE
    return None
