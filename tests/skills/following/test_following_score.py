"""The identity score (skills.following.score): one log-likelihood ratio from position, motion
and appearance, one threshold, and no choice between two that score alike."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from robots.sim.appearance import appearance_of, observed
from skills.following.score import (MARGIN, THRESHOLD, appearance_score, decide,
                                    decide_assignment, identity_score, motion_score,
                                    position_score)


def track(x=0.0, y=0.0, vx=0.0, vy=0.0, look=None):
    return SimpleNamespace(x=x, y=y, vx=vx, vy=vy, appearance=look)


def test_a_track_at_the_gates_edge_with_no_other_evidence_sits_on_the_threshold():
    assert position_score(track(1.0, 0.0), (0.0, 0.0), gate=1.0) == pytest.approx(THRESHOLD)
    assert position_score(track(0.5, 0.0), (0.0, 0.0), gate=1.0) > THRESHOLD
    assert position_score(track(1.5, 0.0), (0.0, 0.0), gate=1.0) < THRESHOLD


def test_walking_unlike_her_costs_and_walking_like_her_does_not():
    assert motion_score(track(vx=0.5), (0.5, 0.0)) == 0.0
    assert motion_score(track(vx=1.4), (0.0, 0.0)) < THRESHOLD      # she stood; he walks fast


def test_appearance_from_simulated_views_separates_her_from_strangers_but_is_capped():
    rng = np.random.default_rng(0)
    her = appearance_of("carla")
    look = np.mean([observed(her, rng) for _ in range(10)], axis=0)
    same = [appearance_score(track(look=observed(her, rng)), look) for _ in range(50)]
    others = [appearance_score(track(look=observed(appearance_of(f"s{k}"), rng)), look)
              for k in range(50)]
    assert np.mean(np.array(same) > 0) >= 0.95 and np.mean(np.array(others) < 0) >= 0.95
    assert max(same + others) <= 6.0 and min(same + others) >= -6.0
    assert appearance_score(track(look=None), look) == 0.0 == appearance_score(track(), None)


def test_the_score_adds_the_cues():
    t = track(0.5, 0.0, vx=0.3)
    assert identity_score(t, (0.0, 0.0), (0.0, 0.0), 1.0) == pytest.approx(
        position_score(t, (0.0, 0.0), 1.0) + motion_score(t, (0.0, 0.0)))


def test_decide_takes_the_clear_best_waits_between_two_alike_and_takes_nobody_below():
    a, b = object(), object()
    assert decide([(-0.1, a), (-0.1 - MARGIN - 0.1, b)]) == (a, False)
    assert decide([(-0.1, a), (-0.1 - MARGIN + 0.1, b)]) == (None, True)
    assert decide([(THRESHOLD - 0.1, a)]) == (None, False)
    assert decide([(-0.5, a), (THRESHOLD - 5.0, b)]) == (a, False)    # b is nobody
    assert decide([]) == (None, False)


def test_a_close_pass_is_decided_on_the_whole_assignment_among_those_who_may_be_her():
    a, b = object(), object()
    # alike on her own account, told apart by where the other one is: the joint decides
    assert decide_assignment([(-0.1, -0.1, a), (-0.3, -0.3 - MARGIN - 0.1, b)]) == (a, False)
    assert decide_assignment([(-0.1, -0.1, a), (-0.3, -0.3 - MARGIN + 0.3, b)]) == (None, True)
    # a joint score below THRESHOLD does not rule out a track that may be her on its own ...
    assert decide_assignment([(-0.5, THRESHOLD - 3.0, a)]) == (a, False)
    # ... and one that may not be her is not taken however well the others fit then
    assert decide_assignment([(THRESHOLD - 0.1, 5.0, a), (-1.0, -1.0, b)]) == (b, False)
    assert decide_assignment([]) == (None, False)


def test_a_view_taken_before_she_was_lost_counts_only_against():
    # her old id may since have been hung on somebody else's legs (HOROS standin8 seed 2):
    # its last view, hers, says nothing for it; a view unlike her still says it is not her
    rng = np.random.default_rng(1)
    her = appearance_of("carla")
    look = np.mean([observed(her, rng) for _ in range(10)], axis=0)
    like, unlike = observed(her, rng), observed(appearance_of("s1"), rng)

    def viewed(view, at):
        return SimpleNamespace(x=0.0, y=0.0, vx=0.0, vy=0.0, appearance=view, appearance_t=at)

    assert appearance_score(viewed(like, 4.0), look, since=5.0) == 0.0
    assert appearance_score(viewed(like, 5.0), look, since=5.0) == 0.0
    assert appearance_score(viewed(like, 5.1), look, since=5.0) == appearance_score(
        viewed(like, 5.1), look) > 0.0
    assert appearance_score(viewed(unlike, 4.0), look, since=5.0) == appearance_score(
        viewed(unlike, 4.0), look) < 0.0
