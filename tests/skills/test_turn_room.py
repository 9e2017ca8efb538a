"""The room to turn on the spot (skills.navigation.footprint.turn_room) and the arbiter's turn
cap it feeds (skills.safety): a box's corners sweep out to its circumscribed radius."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robots.profile import load_profile
from skills.navigation.footprint import TURN_STEP, Footprint, turn_room
from skills.safety import TURN_LAG, arbitrate, turn_rate_within

HOROS = Footprint.of(load_profile("horos"))
LIMITS = load_profile("horos").limits


def _room_by_turning_the_body(footprint, point, radius, margin, sign):
    """The first turn (a fine grid of them) at which the body, turned about its centre, comes
    within `margin` of the disc, nearer than now: the body is turned (`gap_to_points` at each
    heading), not the disc."""
    x, y = point
    now = footprint.gap_to_points(0.0, 0.0, 0.0, np.array([point]))[()] - radius
    for k in range(1, 1801):
        turn = sign * math.radians(k / 10)
        gap = footprint.gap_to_points(0.0, 0.0, turn, np.array([(x, y)]))[()] - radius
        if gap < margin and gap < now - 0.005:
            return abs(turn)
    return math.inf


@pytest.mark.parametrize("seed", range(4))
def test_the_room_is_where_turning_the_body_first_brings_a_corner_near(seed):
    rng = np.random.default_rng(seed)
    for _ in range(25):
        distance, angle = rng.uniform(0.2, 0.6), rng.uniform(-math.pi, math.pi)
        point, radius = (distance * math.cos(angle), distance * math.sin(angle)), 0.1
        if distance - radius < HOROS.inscribed:
            continue                                # inside the body: not a case to turn in
        left, right = turn_room(HOROS, [point], radius, 0.05)
        for room, sign in ((left, 1), (right, -1)):
            expected = _room_by_turning_the_body(HOROS, point, radius, 0.05, sign)
            if math.isinf(expected):
                assert math.isinf(room)
            else:
                # the room is the last checked pose short of the strike: within one step of it
                assert expected - TURN_STEP - 1e-9 <= room <= expected + 1e-9


def test_a_round_base_or_nothing_within_the_corners_reach_leaves_every_turn_free():
    assert turn_room(Footprint.round(0.3), [(0.0, 0.32)], 0.0, 0.05) == (math.inf, math.inf)
    far = HOROS.circumscribed + 0.06
    assert turn_room(HOROS, [(0.0, far)], 0.0, 0.05) == (math.inf, math.inf)
    assert turn_room(HOROS, np.zeros((0, 2)), 0.0, 0.05) == (math.inf, math.inf)


def test_something_already_near_stops_only_the_turn_that_brings_it_nearer():
    # just outside the front-left corner, a little past its diagonal: turning left carries
    # the corner into it at once; turning right carries the corner away, and the rear-left
    # corner only reaches it most of a quarter turn on
    corner = math.hypot(HOROS.length / 2, HOROS.width / 2)
    direction = math.atan2(HOROS.width / 2, HOROS.length / 2) + math.radians(4)
    point = ((corner + 0.02) * math.cos(direction), (corner + 0.02) * math.sin(direction))
    left, right = turn_room(HOROS, [point], 0.0, 0.05)
    assert left < math.radians(6)
    assert right > math.radians(80)


def test_the_arbiter_slows_a_turn_to_stop_within_the_room_and_says_why():
    def call(w, room):
        return arbitrate(0.0, w, link_fresh=True, free_ahead=math.inf, free_behind=math.inf,
                         nearest_person=math.inf, limits=LIMITS, turn_room=room)
    assert call(1.0, (math.inf, math.inf)) == (0.0, 1.0, "")
    v, w, why = call(1.0, (0.0, math.inf))
    assert w == 0.0 and "turning left would sweep a corner" in why
    assert call(-1.0, (0.0, math.inf))[1] == -1.0            # the other way is free
    v, w, why = call(-1.0, (math.inf, 0.2))
    assert -1.0 < w < 0.0 and "turning right" in why
    # the capped rate, held for the lag and then braked, stops within the room
    a = LIMITS.max_turn_accel
    for room in (0.05, 0.2, 0.5):
        rate = turn_rate_within(room, LIMITS)
        assert rate * TURN_LAG + rate * rate / (2 * a) == pytest.approx(room)
    assert call(0.3, (1.0, 1.0))[1] == 0.3                    # slow enough already
