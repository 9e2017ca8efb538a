"""The follower's one question, "is this track my customer?", as one score with one threshold.

The score of a track is a sum of log-likelihood ratios (her against somebody else), one per
cue, so the cues weigh against each other in one currency:

- **position**: `-(d / sigma)² / 2` for a track `d` m from where she is predicted, with
  `sigma` half the re-acquisition gate (which grows with the time unseen): a track at the
  gate's edge scores -2 on position alone.
- **motion**: `-(|v - v_her| / MOTION_SIGMA)² / 2` on the difference between the track's
  velocity and hers (a standing customer does not walk off at 1.4 m/s).
- **appearance** (once her look is known and the track has a camera view):
  `APPEARANCE_A + APPEARANCE_B * h`, clipped to ±APPEARANCE_CAP, on the Hellinger distance
  `h` between her learned look and the track's view. A view taken before she was lost
  (`since`) counts only against: the tracker may have kept her old id alive on somebody
  else's legs since, and her last view on it says nothing about who it is now. A and B are
  the log odds of a logistic regression calibrated on simulated views
  (`python benchmarks/calibrate_identity.py`, 4000 pairs, seeds 0 and 1: 18.7 - 109.6 h and
  17.6 - 103.0 h; a stranger scores above 0 in 0.3 % of pairs, the same person below 0 in
  0.1–0.3 %). The cap keeps look-alikes (a few in a hundred shoppers dress alike) from
  overruling where the tracks are.

A track may be her when its score reaches THRESHOLD (the gate's edge without other evidence).
When the best two candidates score within MARGIN of each other, the follower does not pick:
it stops, says so and waits until they separate (`skills.following.follower`). After a close
pass the margin is taken on the whole assignment (`decide_assignment`): her score plus how
well the other tracks fit the others who came close.
"""
from __future__ import annotations

import math

from skills.people import appearance

THRESHOLD = -2.0          # a track scoring below this is not her
MARGIN = 2.0              # the best must beat the runner-up by this much (e² ≈ 7 times likelier)
MOTION_SIGMA = 0.6        # m/s
APPEARANCE_A = 18.0       # calibrated log odds: A + B * Hellinger distance (see above)
APPEARANCE_B = -106.0
APPEARANCE_CAP = 6.0
MIN_SIGMA = 0.3           # m


def position_score(track, predicted: tuple[float, float], gate: float) -> float:
    sigma = max(gate / 2.0, MIN_SIGMA)
    d = math.hypot(track.x - predicted[0], track.y - predicted[1])
    return -0.5 * (d / sigma) ** 2


def position_log_density(xy: tuple[float, float], predicted: tuple[float, float],
                         gate: float) -> float:
    """log of the 2-D Gaussian density (up to a constant) of a person at `xy` predicted at
    `predicted` with the gate's sigma: unlike `position_score` it counts the spread, so a
    person unseen for a moment (tight gate) explains a point near them better than one
    unseen for seconds (wide gate) explains the same point near her."""
    sigma = max(gate / 2.0, MIN_SIGMA)
    d = math.hypot(xy[0] - predicted[0], xy[1] - predicted[1])
    return -0.5 * (d / sigma) ** 2 - 2.0 * math.log(sigma)


def motion_score(track, velocity: tuple[float, float]) -> float:
    dv = math.hypot(track.vx - velocity[0], track.vy - velocity[1])
    return -0.5 * (dv / MOTION_SIGMA) ** 2


def appearance_score(track, look, since: float | None = None) -> float:
    """0 without a known look or a view of the track (no evidence either way). A view taken
    at or before `since` (when she was last seen) counts only against her: her track's
    last view, carried on by legs alone onto a cart's wheels 1.3 m short of her, scored
    +6 and had the follower take the cart for her (HOROS bench_follow standin8 seed 2).
    `since` = math.inf: every view counts only against (a known look-alike among the
    candidates, where no view tells them apart)."""
    if look is None or getattr(track, "appearance", None) is None:
        return 0.0
    h = appearance.distance(look, track.appearance)
    odds = max(-APPEARANCE_CAP, min(APPEARANCE_CAP, APPEARANCE_A + APPEARANCE_B * h))
    seen_at = getattr(track, "appearance_t", None)
    if since is not None and (seen_at is None or seen_at <= since):
        return min(odds, 0.0)
    return odds


def identity_score(track, predicted: tuple[float, float], velocity: tuple[float, float],
                   gate: float, look=None, since: float | None = None) -> float:
    """Log-likelihood ratio that `track` is the customer (see the module's docstring)."""
    return (position_score(track, predicted, gate) + motion_score(track, velocity)
            + appearance_score(track, look, since))


def decide(scored: list[tuple[float, object]]):
    """(choice, ambiguous) from (score, track) pairs: the best track if it reaches THRESHOLD
    and beats the runner-up (also above THRESHOLD) by MARGIN; None and ambiguous=True when
    two are that close; None and False when nobody reaches THRESHOLD."""
    return _ranked([pair for pair in scored if pair[0] >= THRESHOLD])


def decide_assignment(scored: list[tuple[float, float, object]]):
    """`decide` for a close pass, from (her score, joint score, track) triples: a track may
    be her when its own score reaches THRESHOLD; the margin is taken on the joint score of
    the whole assignment (this track is her and the others are who came close with her), so
    where the others are counts too."""
    return _ranked([(joint, track) for own, joint, track in scored if own >= THRESHOLD])


def _ranked(eligible: list[tuple[float, object]]):
    ranked = sorted(eligible, key=lambda p: -p[0])
    if not ranked:
        return None, False
    if len(ranked) > 1 and ranked[0][0] - ranked[1][0] < MARGIN:
        return None, True
    return ranked[0][1], False


__all__ = ["identity_score", "decide", "decide_assignment", "position_log_density",
           "THRESHOLD", "MARGIN"]
