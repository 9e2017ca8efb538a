"""The camera emulator: the simulated world's people drawn where a camera on the robot sees
them, found again by the camera pipeline, in process and over HTTP (MJPEG, as a network camera),
and reachable as `interbot emulate camera`."""
from __future__ import annotations

import math
import re
import signal
import subprocess
import sys
import time
from dataclasses import replace

import pytest

from robots.camera.detector import CameraPersonDetector
from robots.camera.emulator import CameraEmulator
from robots.camera.source import FrameSource
from robots.clock import SimClock
from robots.profile import load_profile
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")


def world_with_person(standing_person, x: float, y: float):
    simulation = Simulation(HOROS, standing_person(x, y), 0, SimClock())
    simulation.advance(0.1)
    return simulation


def true_bearing(world, x: float, y: float) -> float:
    body = world.body
    return math.remainder(math.atan2(y - body.y, x - body.x) - body.th, math.tau)


def test_a_person_in_view_is_drawn_where_the_camera_sees_them(standing_person):
    simulation = world_with_person(standing_person, 0.6, 3.5)      # the robot faces +y
    emulator = CameraEmulator.for_profile(HOROS, simulation.world)
    (distance, bearing, _), = emulator.camera.visible()
    assert bearing == pytest.approx(true_bearing(simulation.world, 0.6, 3.5))
    detector = CameraPersonDetector(_Still(emulator.camera.frame()), emulator.camera.spec,
                                    emulator.camera.lens, threaded=False)
    found, = detector.detect()
    assert math.atan2(found.y, found.x) == pytest.approx(bearing, abs=math.radians(2))
    assert math.hypot(found.x, found.y) == pytest.approx(distance, rel=0.15)


def test_the_head_turns_the_view(standing_person):
    simulation = world_with_person(standing_person, 0.6, 3.5)
    emulator = CameraEmulator.for_profile(HOROS, simulation.world)
    assert emulator.camera.spec.on_head                 # HOROS's camera is its pan-tilt head
    simulation.world.head_pan = math.radians(60)        # looking away to the left
    assert emulator.camera.visible() == []
    simulation.world.head_pan = true_bearing(simulation.world, 0.6, 3.5)
    (_, bearing, _), = emulator.camera.visible()
    assert bearing == pytest.approx(0.0, abs=1e-9)


class _Still:
    def __init__(self, image):
        self.frame = type("F", (), {"t": 0.0, "number": 1, "image": image})()

    def read(self):
        return self.frame

    def fault(self):
        return None


def test_the_stream_is_a_network_camera_for_opencv(standing_person):
    simulation = world_with_person(standing_person, -0.5, 3.0)
    emulator = CameraEmulator.for_profile(HOROS, simulation.world)
    host, port = emulator.serve_tcp("127.0.0.1", 0)
    emulator.start_clock()                              # frames of the world as it stands
    spec = replace(emulator.camera.spec, on_head=False)
    detector = CameraPersonDetector(FrameSource(f"http://{host}:{port}/video.mjpg"), spec,
                                    emulator.camera.lens)
    try:
        detector.open()
        found, deadline = [], time.monotonic() + 5
        while not found and time.monotonic() < deadline:
            found = detector.detect()
            time.sleep(0.05)
        assert found
        assert math.atan2(found[0].y, found[0].x) == pytest.approx(
            true_bearing(simulation.world, -0.5, 3.0), abs=math.radians(2))
        assert detector.fault() is None
    finally:
        detector.close()
        emulator.close()


def test_emulate_camera_prints_the_stream_address():
    proc = subprocess.Popen([sys.executable, "-c", "from applications.cli import main; "
                             "raise SystemExit(main())", "emulate", "camera"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        match = re.search(r"connect to: (http://127\.0\.0\.1:\d+/video\.mjpg)", line)
        assert match, line
        source = FrameSource(match.group(1))
        source.open()
        deadline = time.monotonic() + 5
        while source.read() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        frame = source.read()
        source.close()
        assert frame is not None and frame.image.shape == (480, 640, 3)
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=10)
        assert proc.returncode == 0 and "stopped" in out
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_a_network_camera_that_stops_is_a_fault_until_it_streams_again(standing_person):
    simulation = world_with_person(standing_person, -0.5, 3.0)
    first = CameraEmulator.for_profile(HOROS, simulation.world)
    host, port = first.serve_tcp("127.0.0.1", 0)
    first.start_clock()
    source = FrameSource(f"http://{host}:{port}/video.mjpg")
    second = None
    try:
        source.open()
        deadline = time.monotonic() + 5
        while source.read() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert source.read() is not None and source.fault() is None
        first.close()                                       # the camera goes away
        deadline = time.monotonic() + 5
        while source.fault() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert "no frame for" in source.fault()
        frames = source.frames
        second = CameraEmulator.for_profile(HOROS, simulation.world)
        second.serve_tcp("127.0.0.1", port)                 # and comes back at the same address
        second.start_clock()
        deadline = time.monotonic() + 8
        while (source.fault() is not None or source.frames == frames) and \
                time.monotonic() < deadline:
            time.sleep(0.05)
        assert source.fault() is None and source.frames > frames
    finally:
        source.close()
        first.close()
        if second is not None:
            second.close()
