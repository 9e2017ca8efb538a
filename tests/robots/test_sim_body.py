"""The unicycle body: clamped commands, acceleration limits, collision stop."""
import math

import numpy as np
import pytest

from robots.profile import load_profile
from robots.sim.body import BUMPER_FRONT, BUMPER_REAR, Obstacles, UnicycleBody

LIMITS = load_profile("horos").limits
WALL_AHEAD = Obstacles(np.array([[1.0, -2.0, 1.0, 2.0]]), np.zeros((0, 3)))
NOTHING = Obstacles(np.zeros((0, 4)), np.zeros((0, 3)))


def body(x=0.0, y=0.0, th=0.0):
    return UnicycleBody(x, y, th, LIMITS, radius=0.26)


def test_command_is_clamped_and_nan_is_zero():
    b = body()
    b.set_command(5.0, -10.0)
    assert (b.cmd_v, b.cmd_w) == (LIMITS.max_speed, -LIMITS.max_turn_rate)
    b.set_command(float("nan"), float("inf"))
    assert (b.cmd_v, b.cmd_w) == (0.0, 0.0)


def test_speed_ramps_within_the_acceleration_limits():
    b = body()
    b.set_command(LIMITS.max_speed, LIMITS.max_turn_rate)
    speeds = []
    for _ in range(40):
        b.step(0.05, NOTHING)
        speeds.append((b.v, b.w))
    v, w = np.array(speeds).T
    assert np.all(np.diff(np.r_[0.0, v]) <= LIMITS.max_accel * 0.05 + 1e-12)
    assert np.all(np.diff(np.r_[0.0, w]) <= LIMITS.max_turn_accel * 0.05 + 1e-12)
    assert v[-1] == LIMITS.max_speed and w[-1] == LIMITS.max_turn_rate


def test_straight_motion_covers_the_integrated_distance():
    b = body()
    b.set_command(0.4, 0.0)
    for _ in range(100):                       # 5 s: 0.8 s ramp to 0.4 m/s, then cruise
        b.step(0.05, NOTHING)
    expected = 0.5 * 0.4 * 0.8 + 0.4 * (5.0 - 0.8)
    assert b.x == pytest.approx(expected, abs=0.02)
    assert b.y == pytest.approx(0.0, abs=1e-12)


def test_turning_on_the_spot_keeps_the_position_and_wraps_heading():
    b = body(th=3.0)
    b.set_command(0.0, 1.0)
    for _ in range(40):
        b.step(0.05, NOTHING)
    assert (b.x, b.y) == (0.0, 0.0)
    assert -math.pi <= b.th <= math.pi
    assert b.th < 0                             # passed +pi and wrapped


def test_driving_into_a_wall_stops_with_front_bumper():
    b = body()
    b.set_command(0.5, 0.0)
    for _ in range(200):
        b.step(0.05, WALL_AHEAD)
    assert b.x <= 1.0 - 0.26 + 1e-9             # never overlaps the wall
    assert b.x > 0.6
    assert b.stalled and b.bumpers == BUMPER_FRONT and b.v == 0.0


def test_backing_away_from_the_wall_is_allowed_and_clears_the_stall():
    b = body(x=0.75)
    b.set_command(0.5, 0.0)
    b.step(0.05, WALL_AHEAD)
    assert b.stalled
    b.set_command(-0.2, 0.0)
    b.step(0.05, WALL_AHEAD)
    assert not b.stalled and b.bumpers == 0 and b.x < 0.75


def test_reversing_into_a_person_sets_the_rear_bumper():
    person = Obstacles(np.zeros((0, 4)), np.array([[-0.6, 0.0, 0.2]]))
    b = body()
    b.set_command(-0.3, 0.0)
    for _ in range(100):
        b.step(0.05, person)
    assert b.stalled and b.bumpers == BUMPER_REAR
    assert b.x >= -0.6 + 0.2 + 0.26 - 1e-9


from hypothesis import given, settings
from hypothesis import strategies as st

from robots.sim.floor import load_floor

OFFICE = Obstacles(load_floor().segments, np.zeros((0, 3)))
commands = st.lists(st.tuples(st.floats(-1.0, 1.0), st.floats(-2.0, 2.0),
                              st.integers(1, 40)), min_size=1, max_size=8)


@settings(max_examples=60, deadline=None)
@given(x=st.floats(-9.5, 9.5), y=st.floats(-0.9, 0.9), th=st.floats(-math.pi, math.pi),
       plan=commands)
def test_the_body_never_enters_a_wall(x, y, th, plan):
    b = body(x, y, th)
    assert b.clearance(b.x, b.y, OFFICE) >= 0.0
    for v, w, steps in plan:
        b.set_command(v, w)
        for _ in range(steps):
            b.step(0.05, OFFICE)
            assert b.clearance(b.x, b.y, OFFICE) >= 0.0
            assert abs(b.v) <= LIMITS.max_speed and abs(b.w) <= LIMITS.max_turn_rate
