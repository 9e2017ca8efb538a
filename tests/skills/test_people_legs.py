"""The leg detector on synthetic scans: ray-cast leg circles in front of a wall."""
from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robots.devices import LaserScan
from skills.people import detect_legs

ANGLES = np.radians(np.arange(-90.0, 90.5, 1.0))   # the profiles' 181-beam, 180 degree laser
LEG_RADIUS = 0.06


def scan_of(legs, wall_x=6.0, origin=(0.0, 0.0, 0.0), noise=0.0, seed=0):
    """Ranges from `origin` to the nearest leg circle, or to a wall at x = wall_x."""
    ox, oy, _ = origin
    ranges = np.full(len(ANGLES), math.inf)
    for k, a in enumerate(ANGLES):
        dx, dy = math.cos(a), math.sin(a)
        best = (wall_x - ox) / dx if dx > 1e-6 else math.inf
        for cx, cy in legs:
            fx, fy = ox - cx, oy - cy
            b = fx * dx + fy * dy
            disc = b * b - (fx * fx + fy * fy - LEG_RADIUS ** 2)
            if disc >= 0 and -b - math.sqrt(disc) > 0:
                best = min(best, -b - math.sqrt(disc))
        ranges[k] = best if best < 8.0 else math.inf
    if noise:
        ranges = ranges + np.random.default_rng(seed).normal(0, noise, len(ranges))
    return LaserScan(t=1.5, angles=ANGLES, ranges=ranges, origin=origin)


def test_two_legs_make_one_person_at_their_midpoint():
    (person,) = detect_legs(scan_of([(2.0, 0.12), (2.05, -0.1)]))
    assert person.source == "laser" and person.t == 1.5
    assert math.dist((person.x, person.y), (2.025, 0.01)) < 0.05
    assert person.cov[0][0] > 0 and person.cov[0][1] == 0


def test_an_empty_hallway_and_a_bare_wall_give_nobody():
    assert detect_legs(scan_of([])) == []
    assert detect_legs(scan_of([], wall_x=1.0)) == []


def test_the_wall_seen_between_two_legs_is_not_a_leg():
    for wall in (2.5, 3.0, 4.0):
        (person,) = detect_legs(scan_of([(2.0, 0.14), (2.0, -0.14)], wall_x=wall))
        assert abs(person.y) < 0.05


def test_a_wall_at_a_grazing_angle_gives_nobody():
    """The hallway wall seen along its length: the range grows in steps from beam to beam."""
    angles = ANGLES
    with np.errstate(divide="ignore"):
        ranges = np.where(np.sin(angles) > 0.05, 1.2 / np.sin(angles), np.inf)
    scan = LaserScan(t=0.0, angles=angles, ranges=np.where(ranges < 8.0, ranges, np.inf),
                     origin=(0.0, 0.0, 0.0))
    assert detect_legs(scan) == []


def test_one_leg_partly_behind_the_other_is_still_a_person():
    (person,) = detect_legs(scan_of([(1.0, 2.125), (1.0, 1.875)]))
    assert math.dist((person.x, person.y), (1.0, 2.0)) < 0.15


def test_two_people_apart_are_two_detections():
    people = detect_legs(scan_of([(2.0, 1.1), (2.0, 0.9), (3.0, -1.0), (3.05, -1.2)]))
    assert sorted(round(p.y, 1) for p in people) == [-1.1, 1.0]


def test_the_laser_origin_is_applied():
    (person,) = detect_legs(scan_of([(2.0, 0.12), (2.0, -0.12)], origin=(0.16, 0.0, 0.0)))
    assert abs(person.x - 2.0) < 0.05


@settings(max_examples=30, deadline=None)
@given(x=st.floats(1.0, 4.0), y=st.floats(-2.0, 2.0), stride=st.floats(0.15, 0.35),
       noise_seed=st.integers(0, 1000))
def test_a_person_anywhere_in_range_is_found_near_the_truth(x, y, stride, noise_seed):
    legs = [(x, y + stride / 2), (x, y - stride / 2)]
    people = detect_legs(scan_of(legs, noise=0.01, seed=noise_seed))
    assert len(people) == 1
    assert math.dist((people[0].x, people[0].y), (x, y)) < 0.15
