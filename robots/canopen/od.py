"""The object dictionary of a CiA 402 wheel drive in profile velocity mode, built in code.

Both ends use it: the driver's `canopen.RemoteNode` (its SDO client needs no more than index
and subindex, but names and types make errors readable) and the emulator's `canopen.LocalNode`
(whose SDO server checks existence, access and data length against it). The objects the
driver touches and those CiA 301/402 ask of such a drive (identity, error history, SYNC and
EMCY COB-IDs, option codes, polarity); a real drive's EDS has hundreds more.
"""
from __future__ import annotations

from canopen import ObjectDictionary
from canopen.objectdictionary import ODArray, ODRecord, ODVariable, datatypes as dt

from robots.canopen import protocol as p

DEVICE_TYPE_402 = 0x00020192        # CiA 402 drive, servo
VENDOR_ID = 0x00000000              # CiA's "unassigned"; an emulator claims no maker's id
PRODUCT_CODE = 0x00000402
ERROR_HISTORY = 8                   # entries of the pre-defined error field 0x1003
PV_ONLY = 0x00000004                # supported drive modes 0x6502: bit 2, profile velocity
PDO_MAPPABLE = (p.CONTROLWORD, p.STATUSWORD, p.MODES_OF_OPERATION, p.MODES_DISPLAY, p.POSITION_ACTUAL,
                p.VELOCITY_DEMAND, p.VELOCITY_ACTUAL, p.TARGET_VELOCITY, p.ERROR_CODE)


def _var(name: str, index: int, sub: int, data_type: int, access: str = "rw", default=0) -> ODVariable:
    var = ODVariable(name, index, sub)
    var.data_type = data_type
    var.access_type = access
    var.default = default
    return var


def _pdo_comm(od: ObjectDictionary, index: int, name: str, cob_id: int, rx: bool) -> None:
    record = ODRecord(name, index)
    record.add_member(_var("Highest sub-index supported", index, 0, dt.UNSIGNED8, "const", 5))
    record.add_member(_var("COB-ID", index, 1, dt.UNSIGNED32, "rw", cob_id))
    record.add_member(_var("Transmission type", index, 2, dt.UNSIGNED8, "rw", 0xFF))
    if not rx:
        record.add_member(_var("Inhibit time", index, 3, dt.UNSIGNED16, "rw", 0))
    record.add_member(_var("Event timer", index, 5, dt.UNSIGNED16, "rw", 0))
    od.add_object(record)


def _pdo_map(od: ObjectDictionary, index: int, name: str) -> None:
    record = ODRecord(name, index)
    record.add_member(_var("Number of mapped objects", index, 0, dt.UNSIGNED8, "rw", 0))
    for sub in range(1, 5):
        record.add_member(_var(f"Mapped object {sub}", index, sub, dt.UNSIGNED32, "rw", 0))
    od.add_object(record)


def drive_dictionary(node: int) -> ObjectDictionary:
    """The dictionary of drive `node` (PDO COB-IDs are node-specific defaults, all invalid)."""
    od = ObjectDictionary()
    od.add_object(_var("Device type", p.DEVICE_TYPE, 0, dt.UNSIGNED32, "ro", DEVICE_TYPE_402))
    od.add_object(_var("Error register", p.ERROR_REGISTER, 0, dt.UNSIGNED8, "ro", 0))
    history = ODArray("Pre-defined error field", p.PRE_DEFINED_ERROR_FIELD)
    history.add_member(_var("Number of errors", p.PRE_DEFINED_ERROR_FIELD, 0, dt.UNSIGNED8, "rw", 0))
    for sub in range(1, ERROR_HISTORY + 1):
        history.add_member(_var(f"Standard error field {sub}", p.PRE_DEFINED_ERROR_FIELD, sub,
                                dt.UNSIGNED32, "ro", 0))
    od.add_object(history)
    od.add_object(_var("COB-ID SYNC", p.COB_ID_SYNC, 0, dt.UNSIGNED32, "rw", p.SYNC_ID))
    od.add_object(_var("COB-ID EMCY", p.COB_ID_EMCY, 0, dt.UNSIGNED32, "rw", p.emcy_id(node)))
    consumer = ODArray("Consumer heartbeat time", p.CONSUMER_HEARTBEAT)
    consumer.add_member(_var("Number of entries", p.CONSUMER_HEARTBEAT, 0, dt.UNSIGNED8, "const", 1))
    consumer.add_member(_var("Consumer heartbeat time 1", p.CONSUMER_HEARTBEAT, 1, dt.UNSIGNED32))
    od.add_object(consumer)
    od.add_object(_var("Producer heartbeat time", p.PRODUCER_HEARTBEAT, 0, dt.UNSIGNED16, "rw", 0))
    identity = ODRecord("Identity object", p.IDENTITY)
    identity.add_member(_var("Highest sub-index supported", p.IDENTITY, 0, dt.UNSIGNED8, "const", 4))
    for sub, name, value in ((1, "Vendor-ID", VENDOR_ID), (2, "Product code", PRODUCT_CODE),
                             (3, "Revision number", 0x00010000), (4, "Serial number", node)):
        identity.add_member(_var(name, p.IDENTITY, sub, dt.UNSIGNED32, "ro", value))
    od.add_object(identity)
    for n in (1, 2):
        _pdo_comm(od, 0x1400 + n - 1, f"RPDO{n} communication parameter",
                  p.PDO_INVALID | p.rpdo_id(n, node), rx=True)
        _pdo_map(od, 0x1600 + n - 1, f"RPDO{n} mapping parameter")
        _pdo_comm(od, 0x1800 + n - 1, f"TPDO{n} communication parameter",
                  p.PDO_INVALID | p.tpdo_id(n, node), rx=False)
        _pdo_map(od, 0x1A00 + n - 1, f"TPDO{n} mapping parameter")
    for name, index, data_type, access in (
            ("Abort connection option code", p.ABORT_CONNECTION_OPTION, dt.INTEGER16, "rw"),
            ("Error code", p.ERROR_CODE, dt.UNSIGNED16, "ro"),
            ("Controlword", p.CONTROLWORD, dt.UNSIGNED16, "rw"),
            ("Statusword", p.STATUSWORD, dt.UNSIGNED16, "ro"),
            ("Quick stop option code", p.QUICK_STOP_OPTION, dt.INTEGER16, "rw"),
            ("Disable operation option code", p.DISABLE_OPERATION_OPTION, dt.INTEGER16, "rw"),
            ("Fault reaction option code", p.FAULT_REACTION_OPTION, dt.INTEGER16, "rw"),
            ("Polarity", p.POLARITY, dt.UNSIGNED8, "rw"),
            ("Supported drive modes", p.SUPPORTED_DRIVE_MODES, dt.UNSIGNED32, "ro"),
            ("Modes of operation", p.MODES_OF_OPERATION, dt.INTEGER8, "rw"),
            ("Modes of operation display", p.MODES_DISPLAY, dt.INTEGER8, "ro"),
            ("Position actual value", p.POSITION_ACTUAL, dt.INTEGER32, "ro"),
            ("Velocity demand value", p.VELOCITY_DEMAND, dt.INTEGER32, "ro"),
            ("Velocity actual value", p.VELOCITY_ACTUAL, dt.INTEGER32, "ro"),
            ("Max profile velocity", p.MAX_PROFILE_VELOCITY, dt.UNSIGNED32, "rw"),
            ("Profile acceleration", p.PROFILE_ACCELERATION, dt.UNSIGNED32, "rw"),
            ("Profile deceleration", p.PROFILE_DECELERATION, dt.UNSIGNED32, "rw"),
            ("Quick stop deceleration", p.QUICK_STOP_DECELERATION, dt.UNSIGNED32, "rw"),
            ("Target velocity", p.TARGET_VELOCITY, dt.INTEGER32, "rw")):
        od.add_object(_var(name, index, 0, data_type, access, 0))
    for index in PDO_MAPPABLE:
        od[index].pdo_mappable = True
    od[p.QUICK_STOP_OPTION].default = 2
    od[p.DISABLE_OPERATION_OPTION].default = 0      # CiA 402: disable drive function (coast)
    od[p.FAULT_REACTION_OPTION].default = 2         # stop on the quick-stop ramp
    od[p.SUPPORTED_DRIVE_MODES].default = PV_ONLY
    od[p.ABORT_CONNECTION_OPTION].default = 1
    return od
