"""The emulated camera, as the EVI-D31 manual describes it: replies, sockets, speeds, limits.

Commands and expected replies are the manual's byte listings (docs/visca.md); the speeds are
its D31 table (pan 18h = 80 deg/s, tilt 14h = 50 deg/s; units: 8.8 per degree of pan, 12 per
degree of tilt).
"""
from __future__ import annotations

import math

import pytest

from robots.profile import load_profile
from robots.sim.simulation import Simulation
from robots.clock import SimClock
from robots.visca.emulator import Camera, ViscaEmulator
from robots.visca import protocol as p

HOROS = load_profile("horos")


def b(text: str) -> bytes:
    return bytes.fromhex(text)


def run(camera: Camera, seconds: float, dt: float = 0.01) -> bytes:
    out = b""
    for _ in range(round(seconds / dt)):
        out += camera.step(dt)
    return out


def test_start_up_replies():
    camera = Camera()
    assert camera.receive(b("88 30 01 FF")) == b("88 30 02 FF")
    assert camera.receive(b("88 01 00 01 FF")) == b("88 01 00 01 FF")
    assert camera.receive(b("81 01 00 01 FF")) == b("90 50 FF")
    assert camera.receive(b("81 09 00 02 FF")) == b("90 50 00 20 04 02 01 00 02 FF")
    assert camera.receive(b("81 09 06 12 FF")) == b("90 50 00 00 00 00 00 00 00 00 FF")


def test_absolute_position_is_acknowledged_then_completed_on_arrival():
    camera = Camera()
    # pan 0370h (+100 deg) at 18h (80 deg/s), tilt 0 : 1.25 s
    assert camera.receive(b("81 01 06 02 18 14 00 03 07 00 00 00 00 00 FF")) == b("90 41 FF")
    assert run(camera, 1.2) == b""
    assert camera.receive(b("81 09 06 12 FF"))[2:6] != b("00 03 07 00")
    assert run(camera, 0.1) == b("90 51 FF")
    assert camera.receive(b("81 09 06 12 FF")) == b("90 50 00 03 07 00 00 00 00 00 FF")


@pytest.mark.parametrize("code, deg_s", [(0x18, 80.0), (0x0C, 40.0), (0x01, 80.0 / 24)])
def test_pan_speed_follows_the_d31_table(code, deg_s):
    camera = Camera()
    camera.receive(p.absolute_position(1, code, 0x14, 0x370, 0))
    run(camera, 0.5)
    assert camera.pan / 8.8 == pytest.approx(deg_s * 0.5, abs=0.2)


def test_tilt_speed_follows_the_d31_table():
    camera = Camera()
    camera.receive(p.absolute_position(1, 0x18, 0x14, 0, 0x12C))
    run(camera, 0.3)
    assert camera.tilt / 12.0 == pytest.approx(50.0 * 0.3, abs=0.2)


def test_the_rated_speed_caps_the_table():
    camera = Camera(rated_pan_deg_s=40.0)
    camera.receive(p.absolute_position(1, 0x18, 0x14, 0x370, 0))
    run(camera, 0.5)
    assert camera.pan / 8.8 == pytest.approx(20.0, abs=0.2)


def test_a_second_motion_while_one_runs_is_not_executable_until_cancelled():
    camera = Camera()
    assert camera.receive(p.absolute_position(1, 0x01, 0x01, 0x370, 0)) == b("90 41 FF")
    assert camera.receive(p.home(1)) == b("90 62 41 FF")
    assert camera.receive(b("81 21 FF")) == b("90 61 04 FF")
    stopped = camera.pan
    assert run(camera, 0.5) == b""
    assert camera.pan == stopped                        # cancelled: it stays where it was
    assert camera.receive(b("81 21 FF")) == b("90 61 05 FF")   # nothing left to cancel
    assert camera.receive(p.home(1)) == b("90 41 FF")


def test_pan_tilt_drive_completes_at_once_and_stops_at_the_limit():
    camera = Camera(pan_limits=(-0x370, 440))           # a narrower right limit: 50 deg
    assert camera.receive(b("81 01 06 01 18 14 02 03 FF")) == b("90 41 FF 90 51 FF")
    run(camera, 3.0)
    assert camera.pan == 440
    assert camera.receive(b("81 01 06 01 18 14 03 03 FF")) == b("90 41 FF 90 51 FF")
    assert camera.motion is None


def test_relative_position_stops_at_the_limit():
    camera = Camera()
    camera.receive(p.relative_position(1, 0x18, 0x14, 0x370, 0))
    run(camera, 1.5)
    camera.receive(p.relative_position(1, 0x18, 0x14, 0x370, -400))
    assert run(camera, 1.5) == b("90 51 FF")
    assert camera.position == (0x370, -0x12C)


def test_absolute_beyond_the_profile_limit_stops_at_it():
    camera = Camera(tilt_limits=(-120, 120))            # 10 deg each way
    camera.receive(p.absolute_position(1, 0x18, 0x14, 0, 0x12C))
    run(camera, 1.0)
    assert camera.position == (0, 120)


@pytest.mark.parametrize("listing", [
    "81 01 06 02 18 14 00 03 07 01 00 00 00 00 FF",   # pan 0371h: beyond the D31's range
    "81 01 06 02 00 14 00 00 00 00 00 00 00 00 FF",   # speed 00
    "81 01 04 07 02 FF",                              # zoom: not this camera's business
    "81 01 06 FF",
])
def test_bad_commands_get_a_syntax_error(listing):
    camera = Camera()
    assert camera.receive(b(listing)) == b("90 60 02 FF")
    assert camera.counts["syntax_errors"] == 1
    assert camera.motion is None


def test_packets_for_another_camera_are_not_answered():
    camera = Camera()
    assert camera.receive(b("82 09 06 12 FF")) == b""
    assert camera.counts["other_address"] == 1


def test_if_clear_stops_the_head_and_frees_the_sockets():
    camera = Camera()
    camera.receive(p.absolute_position(1, 0x01, 0x01, 0x370, 0))
    run(camera, 0.2)
    assert camera.receive(b("81 01 00 01 FF")) == b("90 50 FF")
    assert camera.motion is None and not camera.busy


def test_for_profile_takes_the_limits_and_rate_of_horos():
    emulator = ViscaEmulator.for_profile(HOROS)
    camera = emulator.camera
    assert camera.model is p.EVI_D31
    assert camera.pan_limits == (-0x370, 0x370) and camera.tilt_limits == (-0x12C, 0x12C)
    assert camera.rated_pan == pytest.approx(80.0)


def test_the_world_head_is_the_cameras_head():
    simulation = Simulation(HOROS, None, 0, SimClock())
    emulator = ViscaEmulator.for_profile(HOROS, simulation.world)
    emulator.attach(simulation)
    emulator.receive(p.absolute_position(1, 0x18, 0x14, 0x370, -0x12C))
    simulation.advance(2.0)
    assert math.degrees(simulation.world.head_pan) == pytest.approx(100.0)
    assert math.degrees(simulation.world.head_tilt) == pytest.approx(-25.0)
    emulator.close()
