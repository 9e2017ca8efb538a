"""The follower's phase machine (skills.following.follower), without a world: starting and its
parameters. Its runs in the simulated store are tests/skills/test_following.py."""
from __future__ import annotations

import pytest

from follow_fakes import follower
from skills.following import NO_CUSTOMER


def test_follow_without_anyone_fails_with_a_reason():
    following, _ = follower()
    status = following.follow(0.0)
    assert status.failed and status.reason.startswith(NO_CUSTOMER)


def test_bad_parameters_name_the_field_and_range():
    following, _ = follower()
    with pytest.raises(ValueError, match="distance = 9.0 is outside 0.5 .. 5.0"):
        following.follow(0.0, distance=9.0)
    with pytest.raises(ValueError, match="min_distance = 1.5 m is more than distance"):
        following.follow(0.0, distance=1.2, min_distance=1.5)
