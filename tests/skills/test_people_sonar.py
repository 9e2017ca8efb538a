"""Sonar person candidates: only what is clearly nearer than the background, cone-wide."""
from __future__ import annotations

import math

import numpy as np

from robots.profile import load_profile
from skills.people.sonar import sonar_candidates

SONAR = load_profile("horos").sonar


def test_a_person_in_front_is_one_candidate_with_a_cone_wide_covariance():
    background = np.full(16, 5.0)
    ranges = background.copy()
    ranges[3] = ranges[4] = 1.3            # the two front sonars (+-10 deg) see a body at 1.3 m
    (candidate,) = sonar_candidates(2.0, ranges, SONAR.poses, SONAR.cone, background)
    assert candidate.source == "sonar" and candidate.t == 2.0
    assert math.dist((candidate.x, candidate.y), (1.67, 0.0)) < 0.05
    along, across = candidate.cov[0][0], candidate.cov[1][1]
    assert across > 4 * along               # we know the range, not where in the cone


def test_the_unchanged_background_gives_nobody():
    background = np.array([1.0, 2.0, 5.0, np.inf] * 4)
    assert sonar_candidates(0.0, background, SONAR.poses, SONAR.cone, background) == []


def test_without_a_background_every_near_echo_counts_and_far_ones_do_not():
    ranges = np.full(16, np.inf)
    ranges[0], ranges[12] = 1.0, 4.0        # a left-side echo; a rear one beyond max_range
    (candidate,) = sonar_candidates(0.0, ranges, SONAR.poses, SONAR.cone)
    assert candidate.y > 1.0 and abs(candidate.x) < 0.2
