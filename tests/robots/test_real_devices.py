"""A real HOROS opened with `--port`: the base over P2OS, and the head and camera the profile's
[head] / [camera] name, each through its own wire or file (emulators and a drawn video here)."""
from __future__ import annotations

import math
import time

import cv2
import pytest

from robots.camera.detector import CameraPersonDetector
from robots.camera.intrinsics import Intrinsics
from robots.clock import RealClock
from robots.exceptions import ProfileError, RobotError
from robots.hardware import open_hardware
from robots.p2os.emulator import P2OSEmulator
from robots.profile import PROFILE_DIR, load_profile
from robots.sim.simulation import Simulation
from robots.visca.driver import ViscaHead
from robots.visca.emulator import ViscaEmulator
from tests.robots.camera_scenes import blank, person_at, smooth
from tests.waiting import wait_until

HOROS = load_profile("horos")


@pytest.fixture
def base_url():
    """A P2OS emulator (HOROS) on a pty, as `interbot emulate p2os --pty` would serve it."""
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    emulator.attach(simulation)
    url = emulator.serve_pty()
    emulator.start_clock(simulation)
    yield url
    emulator.close()


@pytest.fixture
def head_emulator():
    emulator = ViscaEmulator.for_profile(HOROS)
    emulator.start_clock()
    yield emulator
    emulator.close()


def profile_with(tmp_path, **tables: str):
    """HOROS's profile with lines added to (or tables appended after) its own."""
    text = (PROFILE_DIR / "horos.toml").read_text()
    for table, lines in tables.items():
        if f"[{table}]\n" in text:
            text = text.replace(f"[{table}]\n", f"[{table}]\n{lines}\n", 1)
        else:
            text += f"\n[{table}]\n{lines}\n"
    path = tmp_path / "horos_here.toml"
    path.write_text(text)
    return path


def test_the_head_named_in_the_profile_opens_beside_the_base(tmp_path, base_url, head_emulator):
    profile = profile_with(tmp_path, head=f'device = "visca:{head_emulator.serve_pty()}"')
    hardware = open_hardware(profile, port=base_url)
    try:
        assert isinstance(hardware.head, ViscaHead) and hardware.head.link_up
        assert "pan_tilt" in hardware.capabilities
        hardware.head.point(math.radians(45), 0.0)
        deadline = time.monotonic() + 3
        while abs(math.degrees(hardware.head.read()[0]) - 45) > 0.2 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert math.degrees(head_emulator.camera.radians()[0]) == pytest.approx(45, abs=0.2)
    finally:
        hardware.close()
    assert not hardware.head.link_up


def test_without_a_device_a_real_robot_has_no_head(base_url):
    hardware = open_hardware("horos", port=base_url)
    try:
        assert hardware.head is None and "pan_tilt" not in hardware.capabilities
    finally:
        hardware.close()


def test_a_named_head_that_does_not_answer_is_an_error_naming_it(tmp_path, base_url):
    from robots.link.pty import PtyPair
    with PtyPair() as silent:
        profile = profile_with(tmp_path, head=f'device = "visca:{silent.path}"')
        with pytest.raises(RobotError, match=r"the head of robot 'horos' \(\[head\] device"):
            open_hardware(profile, port=base_url)


def test_a_device_with_an_unknown_driver_is_a_profile_error(tmp_path, base_url):
    profile = profile_with(tmp_path, head='device = "pelco:/dev/ttyUSB1"')
    with pytest.raises(ProfileError, match="one of visca"):
        open_hardware(profile, port=base_url)


def test_the_camera_named_in_the_profile_detects_people(tmp_path, base_url, head_emulator):
    lens = Intrinsics.from_fov(90.0, 640, 480)
    video = str(tmp_path / "visitor.avi")
    writer = cv2.VideoWriter(video, cv2.VideoWriter_fourcc(*"MJPG"), 10.0, (640, 480))
    for _ in range(80):             # 8 s at 10 fps: frames still come after the head is there
        image = blank(lens)
        person_at(image, lens, 2.0, 0.0)
        writer.write(smooth(image))
    writer.release()
    profile = profile_with(
        tmp_path, head=f'device = "visca:{head_emulator.serve_pty()}"',
        camera=f'device = "opencv:{video}"\nhfov_deg = 90.0\non_head = true\nx = 0.1')
    hardware = open_hardware(profile, port=base_url)
    try:
        assert isinstance(hardware.people_detector, CameraPersonDetector)
        hardware.head.point(math.radians(30), 0.0)
        # 80 deg/s: there in 0.4 s on a quiet machine; waited for, not slept, so that a
        # loaded machine's slower emulator thread does not make the head still on its way
        assert wait_until(lambda: abs(math.degrees(hardware.head.read()[0]) - 30) < 0.5,
                          timeout=10.0), hardware.head.read()
        # Frames are searched one after another on the detector's thread. What it found until
        # now, and the first batch it hands over next (whose frame it may have taken with the
        # head still turning), are dropped; the batch after that read the head once there.
        hardware.people_detector.detect()
        found = []
        for _ in range(2):
            found = []
            deadline = time.monotonic() + 3
            while not found and time.monotonic() < deadline:
                found = hardware.people_detector.detect()
                time.sleep(0.02)
            assert found
        bearing = math.degrees(math.atan2(found[0].y, found[0].x - 0.1))
        assert bearing == pytest.approx(30, abs=2.5)      # the head's pan, added
    finally:
        hardware.close()
