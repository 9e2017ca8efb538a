"""Which of a robot's devices answer where its profile (and `--port`) says they are: the base at
its port, the laser, head and camera at the `device` their tables name. Each is opened with its own
driver, asked for something, and closed; a device that does not answer is reported with the
driver's reason, and the others are still tried. (`interbot robots --check PROFILE`.)"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

from robots.base import base_classes
from robots.clock import RealClock
from robots.profile import load_profile
from robots.real_devices import CAMERA_DRIVERS, HEAD_DRIVERS, split_device

FIRST_FRAME_WITHIN = 3.0     # s a camera may take to deliver its first frame


@dataclass(frozen=True)
class DeviceCheck:
    device: str              # base, laser, head, camera
    address: str
    answers: bool | None     # None: the profile names no address for it
    detail: str


def check_devices(robot, port: str | None = None) -> list[DeviceCheck]:
    """One check per device of `robot` (a profile name or file); `port` overrides the base's."""
    profile = load_profile(robot)
    return [_check_base(profile, port or profile.base.port), _check_laser(profile),
            _check_head(profile), _check_camera(profile)]


def _attempt(device: str, address: str, probe) -> DeviceCheck:
    try:
        return DeviceCheck(device, address, True, probe())
    except Exception as exc:            # any failure is an answer here: say it, go on
        return DeviceCheck(device, address, False, f"{type(exc).__name__}: {exc}")


def _check_base(profile, address: str) -> DeviceCheck:
    def probe() -> str:
        driver = base_classes().get(profile.base.driver)
        if driver is None:
            raise LookupError(f"base driver '{profile.base.driver}' is not installed")
        if hasattr(driver, "for_profile"):
            base = driver.for_profile(profile, address, clock=RealClock())
        else:
            base = driver(profile.limits, address, clock=RealClock(), **profile.base.options)
        try:
            base.open()
            who = getattr(base, "robot_id", None)
            return f"{profile.base.driver} base" + (f" {' '.join(who)}" if who else "")
        finally:
            base.close()
    return _attempt("base", address or "(no port)", probe)


def _check_laser(profile) -> DeviceCheck:
    spec = profile.laser
    if spec is None or not spec.device:
        return DeviceCheck("laser", "", None, "no [laser] device in the profile"
                           + ("" if spec is None else ' (e.g. device = "lms200:/dev/ttyUSB0")'))
    from robots.lasers import check_laser
    return check_laser(profile)


def _check_head(profile) -> DeviceCheck:
    spec = profile.head
    if spec is None or not spec.device:
        return DeviceCheck("head", "", None, "no [head] device in the profile"
                           + ("" if spec is None else ' (e.g. device = "visca:/dev/ttyUSB1")'))

    def probe() -> str:
        from robots.visca.driver import ViscaHead
        _, address = split_device(spec.device, HEAD_DRIVERS, f"{profile.source}: [head]")
        head = ViscaHead.for_profile(profile, address)
        try:
            head.open()
            pan, tilt = head.read()
            return (f"VISCA {head.model.name} at address {head.address}, pan "
                    f"{math.degrees(pan):.1f} deg, tilt {math.degrees(tilt):.1f} deg")
        finally:
            head.close()
    return _attempt("head", spec.device, probe)


def _check_camera(profile) -> DeviceCheck:
    spec = profile.camera
    if spec is None or not spec.device:
        return DeviceCheck("camera", "", None, "no [camera] device in the profile")

    def probe() -> str:
        from robots.camera.source import FrameSource
        _, address = split_device(spec.device, CAMERA_DRIVERS, f"{profile.source}: [camera]",
                                  default="opencv")
        source = FrameSource(address)
        try:
            source.open()
            deadline = time.monotonic() + FIRST_FRAME_WITHIN
            while source.read() is None and time.monotonic() < deadline:
                time.sleep(0.05)
            frame = source.read()
            if frame is None:
                raise TimeoutError(source.fault() or f"no frame within {FIRST_FRAME_WITHIN:g} s")
            height, width = frame.image.shape[:2]
            return f"frames of {width} x {height} px"
        finally:
            source.close()
    return _attempt("camera", spec.device, probe)
