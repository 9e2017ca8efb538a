"""`run`'s device flags: where the laser, head and camera are (`--laser`, `--head`,
`--camera`, over the profile's `device`), and `--wire`, the whole simulated robot on its wires.

The addresses are checked against the robot's profile before anything is opened
(`refuse_bad_addresses`); the rules are the profile's own (robots.addresses, reached through
`behaviors`).
"""
from __future__ import annotations

from applications.commands.arguments import UsageError

DEVICE_FLAGS = {
    "laser": ("KIND:URL[?OPTIONS]", "the laser, over the profile's [laser] device (e.g. "
              "lms200:/dev/ttyUSB0?baud=38400, urg:socket://192.168.0.10:10940; in simulation "
              "lms200:sim is its emulator)"),
    "head": ("visca:URL", "the pan-tilt head, over the profile's [head] device (e.g. "
             "visca:/dev/ttyUSB1; in simulation its emulator stands there)"),
    "camera": ("[opencv:]SOURCE", "the camera, over the profile's [camera] device (a device "
               "index, /dev/video path, rtsp:// or http:// URL, or a video file)"),
}


def add_arguments(parser) -> None:
    group = parser.add_argument_group("devices")
    for device, (metavar, text) in DEVICE_FLAGS.items():
        group.add_argument(f"--{device}", metavar=metavar, help=text)
    group.add_argument("--wire", action="store_true",
                       help="simulation only: the laser and the head too go through their "
                            "drivers, wire protocols and emulators (the base always does), "
                            "the tablet page through its WebSocket to a simulated tablet, "
                            "and the voice through espeak-ng into WAV files (docs/wire.md)")


def options(args) -> dict:
    """open_robot's keyword arguments for the device flags."""
    devices = {device: getattr(args, device, None) for device in DEVICE_FLAGS}
    return {"devices": {k: v for k, v in devices.items() if v is not None} or None,
            "wire": bool(getattr(args, "wire", False))}


def refuse_bad_addresses(args, robot_name: str) -> None:
    """One line, exit 2, before anything opens: an address the robot's profile refuses, or
    --wire on a real base."""
    from behaviors import check_device_addresses
    from behaviors.exceptions import RobotOpenError

    wanted = options(args)
    simulated = getattr(args, "port", None) is None
    if wanted["wire"] and not simulated:
        raise UsageError("argument --wire: puts the simulated robot's devices on their wires; "
                         "a real robot at --port is on its wires already (name its devices "
                         "with --laser, --head, --camera)")
    if wanted["devices"] is None and not wanted["wire"]:
        return
    try:
        check_device_addresses(robot_name, wanted["devices"] or {}, wire=wanted["wire"],
                               simulated=simulated)
    except RobotOpenError as exc:
        raise UsageError(str(exc)) from None
