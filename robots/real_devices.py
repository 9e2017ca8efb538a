"""The devices a robot profile names beside a real base: where each is and which driver speaks
to it. `[head] device = "visca:/dev/ttyUSB1"` (any pyserial URL after the colon: a pty,
`socket://host:port`), `[camera] device = "opencv:/dev/video0"` (the colon part optional: a
device index, a V4L2 path, an rtsp:// or http:// URL, a video file).

Used by `robots.hardware` when a run drives the real robot (`--port`); a device the profile
names but that does not answer is an error naming the device, not a robot without it. In the
simulated world a head the profile names is driven the same way, through its driver and wire
protocol, by the camera emulator in the head's place (as the base's driver talks to its
firmware emulator), and a camera the profile names sees the simulated world drawn
(robots.camera.emulator) through the real camera pipeline; without devices the simulated
head and person detector stand in.
"""
from __future__ import annotations

from robots.devices import PanTiltHead, PersonDetector
from robots.exceptions import ProfileError, RobotError

HEAD_DRIVERS = ("visca",)
CAMERA_DRIVERS = ("opencv",)


def split_device(text: str, drivers: tuple[str, ...], where: str,
                 default: str | None = None) -> tuple[str, str]:
    """(driver, address) of "driver:address"; `default` when the text names no driver."""
    driver, sep, address = text.partition(":")
    if sep and driver in drivers:
        return driver, address
    if default is not None:
        return default, text
    raise ProfileError(f"{where} device = {text!r}: expected DRIVER:ADDRESS with DRIVER one of "
                       f"{', '.join(drivers)} (e.g. \"visca:/dev/ttyUSB1\")")


def open_head(profile, clock=None) -> PanTiltHead | None:
    """The real pan-tilt head the profile's [head] names, opened; None if it names none."""
    spec = profile.head
    if spec is None or not spec.device:
        return None
    _, address = split_device(spec.device, HEAD_DRIVERS, f"{profile.source}: [head]")
    from robots.visca.driver import ViscaHead
    head = ViscaHead.for_profile(profile, address, clock=clock)
    try:
        head.open()
    except BaseException as exc:
        head.close()
        if isinstance(exc, RobotError):
            raise RobotError(f"the head of robot '{profile.name}' ([head] device = "
                             f"{spec.device!r}): {exc}") from exc
        raise
    return head


def open_simulated_head(profile, simulation, clock) -> PanTiltHead | None:
    """In simulation: the profile's wired head through its driver and the VISCA emulator
    stepped with the world, opened; None when the profile names no head device."""
    spec = profile.head
    if spec is None or not spec.device:
        return None
    split_device(spec.device, HEAD_DRIVERS, f"{profile.source}: [head]")
    from robots.visca.driver import ViscaHead
    head = ViscaHead.for_simulation(profile, simulation, clock)
    try:
        head.open()
    except BaseException:
        head.close()
        raise
    return head


def open_camera(profile, clock=None, head: PanTiltHead | None = None) -> PersonDetector | None:
    """The real camera the profile's [camera] names, opened as a person detector; None if it
    names none. A camera on the head (`on_head`) adds the head's pan to its bearings."""
    spec = profile.camera
    if spec is None or not spec.device:
        return None
    _, address = split_device(spec.device, CAMERA_DRIVERS, f"{profile.source}: [camera]",
                              default="opencv")
    from robots.camera.detector import CameraPersonDetector
    camera = CameraPersonDetector.for_profile(profile, address, clock=clock, head=head)
    try:
        camera.open()
    except RobotError as exc:
        raise RobotError(f"the camera of robot '{profile.name}' ([camera] device = "
                         f"{spec.device!r}): {exc}") from exc
    return camera



def open_simulated_camera(profile, simulation, clock,
                          head: PanTiltHead | None = None) -> PersonDetector | None:
    """In simulation: the profile's named camera as the camera pipeline on frames drawn from
    the world; None when the profile names no camera device."""
    spec = profile.camera
    if spec is None or not spec.device:
        return None
    from pathlib import Path

    from robots.camera.detector import CameraPersonDetector, intrinsics_for
    from robots.camera.emulator import WorldCamera, WorldFrameSource
    lens = intrinsics_for(spec, Path(profile.source).parent)
    source = WorldFrameSource(WorldCamera(simulation.world, spec, lens), clock)
    camera = CameraPersonDetector(source, spec, lens, head=head,
                                  threaded=not getattr(clock, "simulated", False))
    camera.open()
    return camera
