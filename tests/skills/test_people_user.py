"""Choosing the user: nearest and approaching, with hysteresis; the small helpers."""
from __future__ import annotations

import numpy as np
import pytest

from skills.people import CONFIRMED, LOST, TENTATIVE, Track, UserSelector, approach_speed, distance

ROBOT = (0.0, 0.0)


def track(id_, x, y, vx=0.0, vy=0.0, status=CONFIRMED):
    return Track(id=id_, x=x, y=y, vx=vx, vy=vy, cov=np.eye(2) * 0.01, status=status,
                 born=0.0, confirmed_at=0.0, last_seen=0.0)


def test_distance_and_approach_speed():
    walker = track(1, 3.0, 4.0, vx=-0.6, vy=-0.8)
    assert distance(walker, ROBOT) == pytest.approx(5.0)
    assert approach_speed(walker, ROBOT) == pytest.approx(1.0)
    assert approach_speed(track(2, 2.0, 0.0, vx=0.5), ROBOT) == pytest.approx(-0.5)
    assert approach_speed(track(3, 2.0, 0.0, vy=1.0), ROBOT) == pytest.approx(0.0)


def test_nearest_confirmed_person_in_range_is_chosen():
    selector = UserSelector(max_range=5.0)
    tracks = [track(1, 3.0, 0.0), track(2, 1.0, 0.0, status=TENTATIVE), track(3, 2.0, 1.0),
              track(4, 6.0, 0.0)]
    assert selector.select(tracks, ROBOT, 0.0).id == 3
    assert selector.select([track(4, 6.0, 0.0)], ROBOT, 0.1) is None


def test_an_approaching_person_beats_a_slightly_nearer_one_standing():
    selector = UserSelector()
    chosen = selector.select([track(1, 2.0, 0.0), track(2, 0.0, 2.5, vy=-1.0)], ROBOT, 0.0)
    assert chosen.id == 2


def test_choice_does_not_flip_between_two_people_at_similar_distance():
    selector = UserSelector(hysteresis=0.5, switch_time=0.5)
    rng = np.random.default_rng(0)
    chosen = []
    for k in range(100):
        a = track(1, 2.0 + rng.normal(0, 0.1), 0.5)
        b = track(2, 2.0 + rng.normal(0, 0.1), -0.5)
        chosen.append(selector.select([a, b], ROBOT, k * 0.1).id)
    assert len(set(chosen)) == 1


def test_a_clearly_better_challenger_takes_over_only_after_switch_time():
    selector = UserSelector(hysteresis=0.5, switch_time=0.5)
    far = track(1, 3.0, 0.0)
    assert selector.select([far], ROBOT, 0.0).id == 1
    near = track(2, 1.0, 0.0)
    picks = [selector.select([far, near], ROBOT, 0.1 * k).id for k in range(1, 10)]
    assert picks[:5] == [1] * 5 and picks[5:] == [2] * 4      # switched once 0.5 s had passed


def test_a_briefly_lost_user_stays_the_user_and_a_deleted_one_does_not():
    selector = UserSelector()
    assert selector.select([track(1, 1.0, 0.0), track(2, 1.5, 0.0)], ROBOT, 0.0).id == 1
    hidden = track(1, 1.0, 0.0, status=LOST)
    assert selector.select([hidden, track(2, 1.5, 0.0)], ROBOT, 0.1).id == 1
    assert selector.select([track(2, 1.5, 0.0)], ROBOT, 0.2).id == 2
    selector.reset()
    assert selector.user_id is None
