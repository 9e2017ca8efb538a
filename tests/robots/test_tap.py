"""The hardware tap and the replay hardware: exact round trips of what the skills read."""
from __future__ import annotations

import math

import numpy as np

from robots.base import BaseState
from robots.devices import Detection, LaserScan
from robots.hardware import open_hardware
from robots.replay import Player, open_replay
from robots.tap import SENSE, Tap, decode_scan, decode_state, encode_state, pack, unpack
from robots.profile import load_profile


def test_base_state_round_trips_exactly_with_inf_and_nan():
    state = BaseState(t=1.25, x=0.1 + 0.2, y=-3.0, th=math.pi, v=0.3, w=-0.1,
                      sonar=(1.5, math.inf, 0.2), bumpers=3, stalled=True, motors_enabled=True,
                      battery=math.nan, link_up=False, extra={"front_bumpers": 1})
    back = decode_state(encode_state(state))
    assert back.sonar == state.sonar and math.isnan(back.battery)
    assert (back.t, back.x, back.y, back.th, back.v, back.w) == (1.25, 0.1 + 0.2, -3.0, math.pi,
                                                                 0.3, -0.1)
    assert (back.bumpers, back.stalled, back.link_up, back.extra) == (3, True, False,
                                                                      {"front_bumpers": 1})


def test_laser_ranges_pack_bit_for_bit():
    ranges = np.array([0.1 + 0.2, math.inf, 7.999999999999999, 1e-300])
    assert np.array_equal(unpack(pack(ranges)), ranges)
    tap = Tap()
    scan = LaserScan(t=2.0, angles=np.linspace(-1, 1, 4), ranges=ranges, origin=(0.16, 0.0, 0.0))
    first = tap.encode_value("laser.read", scan)
    again = tap.encode_value("laser.read", scan)
    assert first["angles"] is not None and again["angles"] is None     # angles sent once
    decoded = decode_scan(again, decode_scan(first, None).angles)
    assert np.array_equal(decoded.angles, scan.angles) and np.array_equal(decoded.ranges, ranges)


def test_the_tap_logs_readings_and_commands_and_replay_plays_them_back():
    hardware = open_hardware("horos", fast=True, emulate=False)
    try:
        hardware.start_tap()
        hardware.sense()
        state = hardware.base.read_state()
        scan1, scan2 = hardware.laser.read(), hardware.laser.read()
        detections = hardware.people_detector.detect()
        hardware.base.command(0.2, 0.1)
        snapshot = hardware.snapshot()
    finally:
        hardware.close()
    keys = [key for key, _ in snapshot["inputs"]]
    assert keys[:2] == [SENSE, "now"]
    assert keys.count("laser.read") == 2 and "base.command" not in keys
    assert snapshot["commands"] == [["base.command", [0.2, 0.1]]]
    assert snapshot["base"]["x"] == state.x and len(snapshot["laser"]["ranges_cm"]) == 181
    replay = open_replay(load_profile("horos"), [snapshot["inputs"]], hardware.devices)
    assert replay.sense() == snapshot["t"]
    assert replay.base.read_state() == state
    again1, again2 = replay.laser.read(), replay.laser.read()
    assert np.array_equal(again1.ranges, scan1.ranges) and np.array_equal(again2.ranges, scan2.ranges)
    assert not np.array_equal(scan1.ranges, scan2.ranges)      # the noise differs per read
    assert replay.people_detector.detect() == [
        Detection(d.t, d.x, d.y, (tuple(d.cov[0]), tuple(d.cov[1])), d.source) for d in detections]
    assert replay.screen.take_press() is None and replay.speaker.busy() is False


def test_a_player_past_its_recording_repeats_the_last_reading():
    player = Player([[["now", 0.0], [SENSE, None], ["now", 0.1]]])
    assert player.take("now") == 0.0
    player.next_segment()
    assert player.take("now") == 0.1 and player.take("now") == 0.1
    assert player.exhausted
