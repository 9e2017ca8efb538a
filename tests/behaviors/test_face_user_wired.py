"""FaceUser in the simulated world on a HOROS whose head and camera are named as devices: the
head goes through the VISCA driver and emulator, the camera is the real camera pipeline (HOG
on frames drawn from the world, the head's pan added), and the head still turns to the
person, who then stands in the middle of the picture."""
from __future__ import annotations

import math

import pytest

from behaviors.robot import open_robot
from robots.profile import PROFILE_DIR

PERSON = (0.8, 2.5)         # from robot_home (0, -0.75) facing +y: 13.8 deg to the right


def wired_profile(tmp_path):
    text = (PROFILE_DIR / "horos.toml").read_text()
    text = text.replace("[head]\n", '[head]\ndevice = "visca:/dev/ttyUSB1"\n', 1)
    text += '\n[camera]\ndevice = "/dev/video0"\nhfov_deg = 90.0\non_head = true\n'
    path = tmp_path / "horos_wired.toml"
    path.write_text(text)
    return path


def test_face_user_with_the_head_and_camera_on_their_wires(tmp_path, standing_person):
    robot = open_robot(wired_profile(tmp_path), fast=True, scenario=standing_person(*PERSON),
                       seed=3)
    try:
        hardware = robot.skills.hardware
        assert type(hardware.head).__name__ == "ViscaHead"
        assert type(hardware.people_detector).__name__ == "CameraPersonDetector"
        for _ in range(10):
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        assert robot.activate("FaceUser") == "head"
        for _ in range(40):
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        world = hardware.simulation.world
        pan = hardware.head.read()[0]
        boxes = hardware.people_detector.boxes
    finally:
        robot.close()
    truth = math.atan2(PERSON[1] - world.body.y, PERSON[0] - world.body.x) - world.body.th
    assert math.degrees(truth) == pytest.approx(-13.8, abs=0.5)
    assert math.degrees(pan) == pytest.approx(math.degrees(truth), abs=3.0)
    assert world.head_pan == pytest.approx(pan, abs=math.radians(0.5))   # the world's head
    assert len(boxes) == 1 and abs(boxes[0].centre[0] - 320) < 20        # now in the middle
