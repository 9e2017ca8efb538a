"""Searching (skills.following.searching), without a world: after `search_after` s unseen the
robot turns round in thirds where she should be, calls out, then looks further along her
trail."""
from __future__ import annotations

import math

from follow_fakes import Speech, follower, track
from skills.following import SEARCHING


def test_it_turns_round_in_thirds_calls_and_then_searches_ahead_along_her_trail():
    speech = Speech()
    following, perception = follower(speech)
    for k in range(11):                                   # she walks along x, then vanishes
        t = 0.1 * k
        perception.believed = (track(1, 2.0 + 0.5 * t, 0.0, t, vx=0.5),)
        if k == 0:
            following.follow(0.0, target=1)
        following.sense(t)
    perception.believed = ()
    bearings, now = [], 1.0
    while now < 1.0 + following.params.search_after + 0.05:
        now += 0.1
        following.sense(now)
    assert following.state.phase == SEARCHING
    assert [text for _, text in speech.said] == [following.params.call]
    for _ in range(4):                                     # each turn done: the next third
        goal = following.motion.goal
        assert goal.kind == "turn_to"
        bearings.append(goal.bearing)
        following.localization.state.th = goal.bearing
        now += 0.1
        following.sense(now)
    steps = {round(abs(math.remainder(b - a, 2 * math.pi)), 2)
             for a, b in zip(bearings, bearings[1:3])}
    assert steps == {round(2 * math.pi / 3, 2)}
    ahead = following._search_goal
    assert ahead is not None and ahead[0] > 2.5 + 2.5      # 3 m on along where she walked
