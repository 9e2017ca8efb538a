"""The objects the CAN driver reads or writes on a drive, and what each standard says of them.

Why a catalogue: a drive from another maker offers what CiA 301 and CiA 402 make mandatory and
a choice of the rest. The driver touches a mandatory object without asking; an optional one
only after an SDO upload showed it exists (abort 0x06020000 / 0x06090011 = it does not), and
then skips it with the note given here. The checklist in docs/canopen.md is this table.
"""
from __future__ import annotations

from dataclasses import dataclass

from robots.canopen import protocol as p

MANDATORY = "mandatory"      # the driver needs it: start-up refuses a drive without it
OPTIONAL = "optional"        # checked for first; skipped with `without` when absent
ABSENT_CODES = (0x06020000, 0x06090011)   # object / sub-index does not exist


@dataclass(frozen=True)
class DriveObject:
    index: int
    sub: int
    name: str
    standard: str            # what CiA 301 / CiA 402 say of it
    need: str                # MANDATORY or OPTIONAL for this driver
    use: str                 # what the driver does with it
    without: str = ""        # what happens when an optional object is absent

    @property
    def key(self) -> str:
        return f"{self.index:#06x}:{self.sub:02x}"


def _pdo(index: int, name: str, use: str) -> DriveObject:
    return DriveObject(index, 0, name, "CiA 301: mandatory for each PDO the drive offers", MANDATORY, use)


OBJECTS = (
    DriveObject(p.DEVICE_TYPE, 0, "device type", "CiA 301: mandatory", MANDATORY,
                "read: the low 16 bits must be 402 (0x0192), a CiA 402 drive"),
    DriveObject(p.IDENTITY, 1, "identity: vendor-ID", "CiA 301: mandatory (sub 1)", MANDATORY,
                "read: logged with product code, revision and serial (subs 2-4, optional)"),
    DriveObject(p.PRODUCER_HEARTBEAT, 0, "producer heartbeat time",
                "CiA 301: mandatory unless the drive offers node guarding instead", MANDATORY,
                "written: the drive's heartbeat, which the host supervises (node guarding is not "
                "implemented)"),
    DriveObject(p.CONSUMER_HEARTBEAT, 1, "consumer heartbeat time", "CiA 301: optional", OPTIONAL,
                "written: the drive supervises the host's heartbeat (node 0x7F)",
                "the drive does not stop by itself when the host dies; the host's own watchdog "
                "and the drives' heartbeat supervision remain"),
    _pdo(0x1400, "RPDO1 communication parameter", "RPDO1 COB-ID and transmission type"),
    _pdo(0x1600, "RPDO1 mapping", "controlword + target velocity (or already so mapped)"),
    DriveObject(0x1401, 1, "RPDO2 COB-ID", "CiA 301: present where the drive offers RPDO2",
                OPTIONAL, "written invalid (bit 31): no second command path",
                "the drive has one RPDO only; nothing to switch off"),
    _pdo(0x1800, "TPDO1 communication parameter", "TPDO1 on every SYNC"),
    _pdo(0x1A00, "TPDO1 mapping", "statusword + velocity actual"),
    _pdo(0x1801, "TPDO2 communication parameter", "TPDO2 on every SYNC"),
    _pdo(0x1A01, "TPDO2 mapping", "position actual"),
    DriveObject(p.CONTROLWORD, 0, "controlword", "CiA 402: mandatory", MANDATORY,
                "the state machine, quick stop, fault reset (SDO at start-up, RPDO1 after)"),
    DriveObject(p.STATUSWORD, 0, "statusword", "CiA 402: mandatory", MANDATORY,
                "the state, read after each step and in TPDO1"),
    DriveObject(p.MODES_OF_OPERATION, 0, "modes of operation",
                "CiA 402: conditional (mandatory where more than one mode is offered)", MANDATORY,
                "written 3 (profile velocity)"),
    DriveObject(p.MODES_DISPLAY, 0, "modes of operation display", "CiA 402: conditional, as 0x6060",
                MANDATORY, "read back: must show 3"),
    DriveObject(p.TARGET_VELOCITY, 0, "target velocity", "CiA 402: mandatory in pv", MANDATORY,
                "written 0 at start-up, then in RPDO1"),
    DriveObject(p.VELOCITY_ACTUAL, 0, "velocity actual value", "CiA 402: mandatory in pv", MANDATORY,
                "in TPDO1: body speed, standstill when stopping, the self-check"),
    DriveObject(p.POSITION_ACTUAL, 0, "position actual value", "CiA 402: optional in pv", MANDATORY,
                "in TPDO2: odometry (this driver has no odometry without it)"),
    DriveObject(p.SUPPORTED_DRIVE_MODES, 0, "supported drive modes", "CiA 402: optional", OPTIONAL,
                "read: bit 2 (pv) must be set",
                "the mode is checked by reading back 0x6061 only"),
    DriveObject(p.PROFILE_ACCELERATION, 0, "profile acceleration", "CiA 402: optional in pv", OPTIONAL,
                "written from the profile's max_accel",
                "the drive accelerates on its own setting; the host's commands are ramped anyway"),
    DriveObject(p.PROFILE_DECELERATION, 0, "profile deceleration", "CiA 402: optional in pv", OPTIONAL,
                "written from the profile's max_accel", "the drive decelerates on its own setting"),
    DriveObject(p.QUICK_STOP_DECELERATION, 0, "quick stop deceleration", "CiA 402: optional", OPTIONAL,
                "written from quick_stop_decel", "quick stops use the drive's own deceleration"),
    DriveObject(p.MAX_PROFILE_VELOCITY, 0, "max profile velocity", "CiA 402: optional", OPTIONAL,
                "written from max_speed and max_turn_rate",
                "only the host's speed limits hold (the drive does not cap the target)"),
    DriveObject(p.QUICK_STOP_OPTION, 0, "quick stop option code", "CiA 402: optional", OPTIONAL,
                "written 2: stop on the quick-stop ramp, then switch on disabled",
                "the drive's own quick-stop reaction (CiA 402's default is 2)"),
    DriveObject(p.DISABLE_OPERATION_OPTION, 0, "disable operation option code", "CiA 402: optional",
                OPTIONAL, "written 1: disable operation brakes on the profile deceleration",
                "disable operation is sent only after standstill (quick stop first)"),
    DriveObject(p.ABORT_CONNECTION_OPTION, 0, "abort connection option code", "CiA 402: optional",
                OPTIONAL, "written 3: quick stop when the host's heartbeat is lost",
                "the drive reacts to a lost host as 0x1029 says, or not at all"),
    DriveObject(p.POLARITY, 0, "polarity", "CiA 402: optional", OPTIONAL,
                "read: a wheel inverted inside the drive (bit 6) must not be right_mirrored too, "
                "and velocity and position must be inverted alike (bits 6 and 7)",
                "the self-check alone catches a position counting against the command"),
    DriveObject(p.ERROR_CODE, 0, "error code", "CiA 402: optional", OPTIONAL,
                "read to explain a drive in Fault", "the fault is named by the statusword only"),
)
BY_KEY = {(o.index, o.sub): o for o in OBJECTS}


def described(index: int, sub: int = 0) -> DriveObject:
    return BY_KEY[(index, sub)]
