"""The fastest the arbiter lets the robot drive now (`Motion.top_speed`): the near-people cap
while someone it is for is near, the profile's top speed otherwise."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from robots.profile import load_profile
from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.motion import Motion
from skills.people.track import CONFIRMED, Track


def person(tid, x, y, vx=0.0, vy=0.0):
    return Track(tid, x, y, vx, vy, np.eye(2) * 0.01, CONFIRMED, 0.0, 0.0, 0.0)


def motion_among(*tracks, followed=None):
    """PERSES's motion skill at the origin facing +x, with these tracked people."""
    localization = SimpleNamespace(state=SimpleNamespace(x=0.0, y=0.0, th=0.0))
    perception = SimpleNamespace(tracks=list(tracks))
    motion = Motion(Blackboard("motion"), EventLog(), base=None,
                    limits=load_profile("perses").limits, localization=localization,
                    perception=perception)
    motion.followed = followed
    return motion


def test_the_top_speed_is_the_profiles_on_an_empty_floor():
    motion = motion_among()
    assert motion.top_speed() == motion.limits.max_speed == 0.6


def test_someone_beside_the_way_ahead_holds_it_to_the_near_people_cap():
    limits = motion_among().limits
    shopper_at_the_shelf = person(2, 0.5, 0.7)               # 0.86 m away, 54 degrees left
    assert motion_among(shopper_at_the_shelf).top_speed() == limits.max_speed_near_people
    far_off = person(2, 1.6, 0.7)                             # 1.75 m: outside 1.5 m
    assert motion_among(far_off).top_speed() == limits.max_speed


def test_people_it_leaves_behind_and_the_customer_walking_away_do_not_cap_it():
    limits = motion_among().limits
    behind = person(2, -1.0, 0.2)                             # passed: driving on widens the gap
    assert motion_among(behind).top_speed() == limits.max_speed
    customer_walking_off = person(1, 1.2, 0.0, vx=0.5)
    assert motion_among(customer_walking_off, followed=1).top_speed() == limits.max_speed
    customer_coming_back = person(1, 1.2, 0.0, vx=-0.5)
    assert (motion_among(customer_coming_back, followed=1).top_speed()
            == limits.max_speed_near_people)
