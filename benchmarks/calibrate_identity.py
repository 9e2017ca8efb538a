"""Calibrates the appearance part of the follower's identity score (skills/following/score.py)
on simulated camera views: how much more likely a Hellinger distance d between a person's
learned look and a fresh view is when the view is of the same person than of somebody else.

People are drawn as the simulator draws them (robots.sim.appearance: one histogram per id,
log-normal noise per view); a look is learned as the follower learns it (the running blend of
LOOK_KNOWN.. views, skills.following.identity); half the pairs are the same person, half are two
different people. A one-dimensional logistic regression of "same" on d gives the log odds
a + b d, the log-likelihood ratio for balanced pairs. It prints a, b and how often a stranger
scores as her.

    python benchmarks/calibrate_identity.py [--people 2000] [--seed 0]
"""
from __future__ import annotations

import argparse

import numpy as np

from robots.sim.appearance import appearance_of, observed
from skills.following.identity import LOOK_KNOWN, LOOK_WEIGHT
from skills.people import appearance


def pairs(people: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(distances, same) for `people` same-person and `people` different-person pairs."""
    rng = np.random.default_rng(seed)
    distances, same = [], []
    for k in range(people):
        true = appearance_of(f"calibration-{seed}-{k}")
        look = None
        for n in range(LOOK_KNOWN + int(rng.integers(0, 20))):
            look = appearance.blend(look, observed(true, rng), max(LOOK_WEIGHT, 1.0 / (n + 1)))
        distances.append(appearance.distance(look, observed(true, rng)))
        same.append(1.0)
        other = appearance_of(f"calibration-{seed}-{k}-other")
        distances.append(appearance.distance(look, observed(other, rng)))
        same.append(0.0)
    return np.array(distances), np.array(same)


def logistic(d: np.ndarray, y: np.ndarray, rounds: int = 50) -> tuple[float, float]:
    """Newton's method for log odds a + b d."""
    w = np.zeros(2)
    x = np.stack([np.ones_like(d), d], axis=1)
    for _ in range(rounds):
        p = 1.0 / (1.0 + np.exp(-(x @ w)))
        gradient = x.T @ (y - p)
        hessian = -(x.T * (p * (1 - p))) @ x - 1e-9 * np.eye(2)
        w -= np.linalg.solve(hessian, gradient)
    return float(w[0]), float(w[1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--people", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    options = parser.parse_args()
    d, y = pairs(options.people, options.seed)
    a, b = logistic(d, y)
    score = a + b * d
    print(f"pairs: {len(d)}; log odds of the same person = {a:.2f} + ({b:.2f}) * distance")
    print(f"same person scoring below 0: {np.mean(score[y == 1] < 0):.3f}; "
          f"stranger scoring above 0: {np.mean(score[y == 0] > 0):.3f}")


if __name__ == "__main__":
    main()
