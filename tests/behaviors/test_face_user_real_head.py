"""FaceUser on a real HOROS (`--port`): the base over P2OS, the pan-tilt head over VISCA and a
camera (a video of a visitor 30 deg to the left, drawn by the test) each through its own wire
or file. FaceUser turns the head, over VISCA, to the person the camera sees; the body stays."""
from __future__ import annotations

import math
import time

import cv2
import pytest

from behaviors.robot import open_robot
from robots.camera.intrinsics import Intrinsics
from robots.clock import RealClock
from robots.p2os.emulator import P2OSEmulator
from robots.profile import PROFILE_DIR, load_profile
from robots.sim.simulation import Simulation
from robots.visca.emulator import ViscaEmulator
from tests.robots.camera_scenes import blank, person_at, smooth

HOROS = load_profile("horos")
VISITOR_DEG = 30.0


@pytest.fixture
def real_horos(tmp_path):
    """A profile naming the head's and camera's addresses, and the P2OS base's address."""
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)          # the base emulator's own world
    base = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    base.attach(simulation)
    base_url = base.serve_pty()
    base.start_clock(simulation)
    head = ViscaEmulator.for_profile(HOROS)
    head.start_clock()
    lens = Intrinsics.from_fov(90.0, 640, 480)
    video = str(tmp_path / "visitor.avi")
    writer = cv2.VideoWriter(video, cv2.VideoWriter_fourcc(*"MJPG"), 10.0, (640, 480))
    for _ in range(150):
        image = blank(lens)
        person_at(image, lens, 2.5, math.radians(VISITOR_DEG))
        writer.write(smooth(image))
    writer.release()
    text = (PROFILE_DIR / "horos.toml").read_text()
    text = text.replace("[head]\n", f'[head]\ndevice = "visca:{head.serve_pty()}"\n', 1)
    # a camera fixed to the body (the video does not follow the head)
    text += f'\n[camera]\ndevice = "opencv:{video}"\nhfov_deg = 90.0\nx = 0.1\n'
    profile = tmp_path / "horos_real.toml"
    profile.write_text(text)
    yield profile, base_url, head
    head.close()
    base.close()


def test_face_user_turns_the_real_head_over_visca(real_horos):
    profile, base_url, head = real_horos
    robot = open_robot(profile, port=base_url)
    try:
        assert "pan_tilt" in robot.capabilities
        start = time.monotonic()
        for _ in range(10):                      # let the tracker confirm the visitor
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        realization = robot.activate("FaceUser")
        for _ in range(30):
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        pan = math.degrees(head.camera.radians()[0])
        events = robot.events()
    finally:
        robot.close()
    assert realization == "head"                 # not "body"
    assert pan == pytest.approx(VISITOR_DEG, abs=4.0), pan
    assert any(pkt[1:4] == b"\x01\x06\x02" for pkt in head.received)   # AbsolutePosition
    assert not [e for e in events if e["kind"] in ("fault", "crash")]
    assert time.monotonic() - start < 30
