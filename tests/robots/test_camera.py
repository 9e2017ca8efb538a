"""The camera person detector on pictures and videos the tests draw themselves: OpenCV's HOG
people detector and frontal-face cascade find them, the calibration turns boxes into bearings
and ranges, a video file plays at its rate on a simulated clock, and faults are said."""
from __future__ import annotations

import math
import time
from dataclasses import replace

import cv2
import numpy as np
import pytest

from robots.camera.detector import CameraPersonDetector, covariance, torso_histogram
from robots.camera.finder import PeopleFinder
from robots.camera.intrinsics import Intrinsics, load_calibration
from robots.camera.source import FrameSource, capture_target
from robots.clock import SimClock
from robots.exceptions import LinkError, ProfileError
from robots.profile import CameraSpec
from tests.robots.camera_scenes import blank, draw_face, person_at, smooth


LENS = Intrinsics.from_fov(90.0, 640, 480)      # fx = fy = 320 px
SPEC = CameraSpec(hfov_deg=90.0, width=640, height=480, x=0.1, detect=("body", "face"))


def write_video(path, frames, fps=10.0) -> str:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), fps,
                             (frames[0].shape[1], frames[0].shape[0]))
    assert writer.isOpened()
    for frame in frames:
        writer.write(frame)
    writer.release()
    return str(path)


def test_intrinsics_from_the_field_of_view():
    assert LENS.fx == pytest.approx(320.0) and (LENS.cx, LENS.cy) == (320.0, 240.0)
    assert LENS.bearing(320) == pytest.approx(0.0)
    assert LENS.bearing(0) == pytest.approx(math.radians(45))      # the left edge: +45 deg
    assert LENS.bearing(640) == pytest.approx(math.radians(-45))
    assert LENS.scaled_to(320, 240).fx == pytest.approx(160.0)


def test_calibration_file_in_opencvs_format(tmp_path):
    path = tmp_path / "cam.yaml"
    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    storage.write("image_width", 640)
    storage.write("image_height", 480)
    storage.write("camera_matrix", np.array([[500.0, 0, 310], [0, 505.0, 250], [0, 0, 1]]))
    storage.write("distortion_coefficients", np.array([[-0.2, 0.05, 0.0, 0.0, 0.0]]))
    storage.release()
    lens = load_calibration(path)
    assert (lens.fx, lens.fy, lens.cx, lens.cy) == (500.0, 505.0, 310.0, 250.0)
    assert lens.distortion[0] == pytest.approx(-0.2)
    # barrel distortion pulls the edge in: undistorted, the bearing there is larger
    assert abs(lens.bearing(10, 250)) > abs(math.atan((10 - 310) / 500.0))
    assert lens.bearing(310, 250) == pytest.approx(0.0, abs=1e-6)


def test_a_bad_calibration_file_names_itself(tmp_path):
    path = tmp_path / "cam.yaml"
    path.write_text("%YAML:1.0\n---\nimage_width: 640\n")
    with pytest.raises(ProfileError, match="cam.yaml: camera_matrix"):
        load_calibration(path)
    with pytest.raises(ProfileError, match="not found"):
        load_calibration(tmp_path / "nothing.yaml")


@pytest.mark.parametrize("distance, bearing_deg", [(2.0, 0.0), (3.0, 20.0), (2.5, -25.0)])
def test_a_drawn_person_is_found_where_they_stand(distance, bearing_deg):
    image = blank(LENS)
    person_at(image, LENS, distance, math.radians(bearing_deg))
    boxes = PeopleFinder(("body",)).find(smooth(image))
    assert len(boxes) == 1 and boxes[0].kind == "body"
    u, _ = boxes[0].centre
    assert math.degrees(LENS.bearing(u)) == pytest.approx(bearing_deg, abs=2.0)


def test_an_empty_scene_has_nobody():
    image = blank(LENS)
    cv2.rectangle(image, (100, 60), (220, 420), (120, 90, 60), -1)      # a door
    cv2.rectangle(image, (400, 300), (600, 360), (60, 60, 60), -1)      # a table
    assert PeopleFinder().find(smooth(image)) == []


def test_a_drawn_face_is_found_and_ranged():
    image = blank(LENS)
    draw_face(image, 200, 240, 80)
    finder = PeopleFinder(("face",))
    boxes = finder.find(cv2.GaussianBlur(image, (5, 5), 0))
    assert len(boxes) == 1 and boxes[0].kind == "face"
    assert boxes[0].w == pytest.approx(100, abs=15)       # the box: a little wider than the face


class StillSource:
    """One picture, delivered once as frame 1 at t = 5 s."""
    def __init__(self, image):
        self.frame = type("F", (), {"t": 5.0, "number": 1, "image": image})()

    def read(self):
        return self.frame

    def fault(self):
        return None


@pytest.mark.parametrize("distance, bearing_deg", [(2.0, 0.0), (3.2, 15.0)])
def test_detections_in_the_robot_frame(distance, bearing_deg):
    image = blank(LENS)
    person_at(image, LENS, distance, math.radians(bearing_deg))
    detector = CameraPersonDetector(StillSource(smooth(image)), SPEC, LENS, threaded=False)
    found = detector.detect()
    assert len(found) == 1
    d = found[0]
    assert (d.t, d.source) == (5.0, "camera")
    bearing = math.atan2(d.y, d.x - SPEC.x)
    assert math.degrees(bearing) == pytest.approx(bearing_deg, abs=2.0)
    assert math.hypot(d.x - SPEC.x, d.y) == pytest.approx(distance, rel=0.15)
    assert d.appearance is not None and len(d.appearance) == 8
    assert sum(d.appearance) == pytest.approx(1.0)
    assert detector.detect() == []                      # the same frame is reported once


def test_a_camera_on_the_head_adds_the_pan():
    class Head:
        def read(self):
            return math.radians(30), 0.0
    image = blank(LENS)
    person_at(image, LENS, 2.0, 0.0)
    spec = replace(SPEC, on_head=True, x=0.0)
    found = CameraPersonDetector(StillSource(smooth(image)), spec, LENS, head=Head(),
                                 threaded=False).detect()
    assert math.degrees(math.atan2(found[0].y, found[0].x)) == pytest.approx(30, abs=2.0)


def test_covariance_is_long_along_the_ray():
    cov = np.array(covariance(3.0, math.pi / 2, SPEC))    # straight to the left
    assert cov[1][1] == pytest.approx((0.2 * 3.0) ** 2)    # range error along y
    assert cov[0][0] == pytest.approx((math.radians(2) * 3.0) ** 2)
    assert np.all(np.linalg.eigvalsh(cov) > 0)


def test_shirts_of_different_colours_look_different():
    red, blue = blank(LENS), blank(LENS)
    person_at(red, LENS, 2.0, 0.0, shirt=(30, 30, 200))
    person_at(blue, LENS, 2.0, 0.0, shirt=(200, 60, 30))
    box = PeopleFinder(("body",)).find(smooth(red))[0]
    h_red, h_blue = torso_histogram(red, box), torso_histogram(blue, box)
    assert np.argmax(h_red) != np.argmax(h_blue)


def test_a_video_plays_at_its_rate_on_a_simulated_clock(tmp_path):
    frames = []
    for i in range(10):                      # a person walking from left to right
        image = blank(LENS)
        person_at(image, LENS, 2.5, math.radians(20 - 4 * i))
        frames.append(smooth(image))
    path = write_video(tmp_path / "walk.avi", frames, fps=5.0)
    clock = SimClock()
    detector = CameraPersonDetector(FrameSource(path, clock=clock), SPEC, LENS)
    detector.open()
    bearings = []
    for _ in range(25):                      # 10 Hz ticks over 2.5 s: 5 frames a second
        found = detector.detect()
        if found:
            bearings.append(math.degrees(math.atan2(found[0].y, found[0].x - SPEC.x)))
        clock.advance(0.1)
    assert detector.source.frames == 10
    assert len(bearings) >= 8
    assert bearings == sorted(bearings, reverse=True)          # she walks to the right
    assert bearings[0] == pytest.approx(20, abs=3) and bearings[-1] < -10
    assert detector.fault() is not None and "ended after 10 frames" in detector.fault()
    detector.close()


def test_a_looping_video_does_not_end(tmp_path):
    path = write_video(tmp_path / "still.avi", [blank(LENS)] * 3, fps=10.0)
    clock = SimClock()
    source = FrameSource(path, clock=clock, loop=True)
    source.open()
    for _ in range(10):
        assert source.read() is not None
        clock.advance(0.1)
    assert source.fault() is None and source.frames >= 9
    source.close()


@pytest.mark.parametrize("address", ["/no/such/video.avi", "/dev/video97"])
def test_a_camera_that_cannot_be_opened_says_what_an_address_is(address):
    with pytest.raises(LinkError, match="device index such as 0"):
        FrameSource(address).open()


def test_addresses():
    assert capture_target("0") == 0 and capture_target(" 2 ") == 2
    assert capture_target("/dev/video0") == "/dev/video0"
    assert capture_target("rtsp://10.0.0.2/stream") == "rtsp://10.0.0.2/stream"


def test_in_real_time_people_are_found_on_a_thread_of_its_own(tmp_path):
    image = blank(LENS)
    person_at(image, LENS, 2.5, math.radians(-20))
    path = write_video(tmp_path / "standing.avi", [smooth(image)] * 30, fps=10.0)
    detector = CameraPersonDetector(FrameSource(path), SPEC, LENS)      # no clock: real time
    assert detector.threaded
    detector.open()
    try:
        found, deadline = [], time.monotonic() + 3
        while not found and time.monotonic() < deadline:
            found = detector.detect()
            time.sleep(0.05)
        assert found and detector._worker.is_alive()
        assert math.degrees(math.atan2(found[0].y, found[0].x - SPEC.x)) == pytest.approx(-20,
                                                                                          abs=2)
    finally:
        detector.close()
    assert detector._worker is None
