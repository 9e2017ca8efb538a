"""Where each device is, from the command line as well as from the profile.

A profile names each device's address in its table (`[laser] device = "lms200:/dev/ttyUSB0"`,
`[head] device = "visca:/dev/ttyUSB1"`, `[camera] device = "opencv:/dev/video0"`). On a lab's
robot the ports move (another USB socket, another adapter), so `interbot run --laser ADDRESS`
(`--head`, `--camera`) names it for one run instead of editing the file. The address is checked
with the profile's own rules before anything is opened, and it needs the profile's table: the
geometry of a laser, the limits of a head and the lens of a camera are the profile's.

`wired_addresses` is the whole simulated robot on the wire (`interbot run --wire`): the laser
and the head each through their driver, wire protocol and emulator in the simulated world, as
the base's driver talks to its firmware emulator. The camera is left out: its emulator draws
the world and OpenCV's detectors see in it what they see, which is a different sensor from the
simulated person detector the applications' scenarios are written for (docs/robots.md).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Mapping

from robots.exceptions import ProfileError
from robots.lasers import SIMULATED, parse_laser_device
from robots.profile import RobotProfile
from robots.real_devices import CAMERA_DRIVERS, HEAD_DRIVERS, split_device

DEVICES = ("laser", "head", "camera")
DEFAULT_LASER = "lms200"        # the SICK laser of the Pioneer and B21r era
EXAMPLES = {"laser": "lms200:/dev/ttyUSB0?baud=38400", "head": "visca:/dev/ttyUSB1",
            "camera": "opencv:/dev/video0"}


def check_address(device: str, text: str, *, simulated: bool) -> str:
    """The address `text` of `device`, checked (ProfileError saying what is allowed). In
    simulation a laser must be the emulator's (`KIND:sim`): a port there would be ignored."""
    where = f"argument --{device}"
    if device not in DEVICES:
        raise ProfileError(f"{device!r} is not a device named on the command line; allowed: "
                           f"{', '.join(DEVICES)}")
    if not text:
        raise ProfileError(f"{where}: empty address; allowed e.g. {EXAMPLES[device]!r}")
    if device == "laser":
        try:
            address = parse_laser_device(text)
        except ValueError as exc:
            raise ProfileError(f"{where} {text!r}: {exc}") from None
        if simulated and address.url != SIMULATED:
            raise ProfileError(f"{where} {text!r}: a port means a real robot, and this run is "
                               f"simulated; add --port for the base, or name the laser's "
                               f"emulator, '{address.kind}:{SIMULATED}'")
    elif device == "head":
        driver, address = split_device(text, HEAD_DRIVERS, where)
        if not address:
            raise ProfileError(f"{where} {text!r}: no address after '{driver}:'; allowed e.g. "
                               f"{EXAMPLES[device]!r}")
    else:
        split_device(text, CAMERA_DRIVERS, where, default="opencv")
    return text


def with_addresses(profile: RobotProfile, addresses: Mapping[str, str | None],
                   *, simulated: bool = False) -> RobotProfile:
    """`profile` with the devices' addresses `addresses` gives (None: the profile's stays)."""
    changes = {}
    for device, text in addresses.items():
        if text is None:
            continue
        check_address(device, text, simulated=simulated)
        spec = getattr(profile, device)
        if spec is None:
            raise ProfileError(f"argument --{device}: robot '{profile.name}' has no [{device}] "
                               f"in its profile ({profile.source}), which says where the "
                               f"{device} sits and what it can do; add the table, then name "
                               f"its address")
        changes[device] = replace(spec, device=text)
    return replace(profile, **changes) if changes else profile


def wired_addresses(profile: RobotProfile) -> dict[str, str]:
    """The addresses that put the simulated robot's laser and head on their wires: the laser's
    own kind (or the LMS 200) at its emulator, the head through VISCA to its emulator."""
    addresses = {}
    if profile.laser is not None:
        kind, query = DEFAULT_LASER, ""
        if profile.laser.device:             # the profile's own laser, with its options
            kind = parse_laser_device(profile.laser.device).kind
            query = profile.laser.device.partition("?")[2]
        addresses["laser"] = f"{kind}:{SIMULATED}" + (f"?{query}" if query else "")
    if profile.head is not None:
        addresses["head"] = f"visca:{SIMULATED}"
    return addresses
