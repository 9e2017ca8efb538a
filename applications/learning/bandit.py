"""Bernoulli multi-armed bandits over per-alternative counts (successes, trials).

A small numpy implementation rather than a library: the statistics a bandit needs are two
counts per alternative, which the store keeps as rows in SQLite (durable, readable by
`interbot learn`), and the choice is a few lines over them. MABWiser (Apache-2.0, last release
2024-08) would add scikit-learn, pandas and seaborn to the robot's dependencies and keep its
state in a pickled model object instead of counts we can write episode by episode.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

METHODS = ("thompson", "ucb")
PRIOR = (1.0, 1.0)            # Beta(1, 1): every success rate equally likely before any trial


def choose(successes: Sequence[float], trials: Sequence[float], rng: np.random.Generator,
           method: str = "thompson", frozen: bool = False, min_share: float = 0.0) -> int:
    """The index of the alternative to try next.

    `frozen`: exploit only (the best estimated success so far, no exploring). `min_share`: an
    alternative tried less than this share of all trials is tried first (lowest share wins),
    so none is ever starved; it applies when frozen too."""
    s = np.asarray(successes, dtype=float)
    n = np.asarray(trials, dtype=float)
    starved = below_share(n, min_share)
    if starved is not None:
        return starved
    if frozen:
        return exploit(s, n)
    if method == "ucb":
        return ucb(s, n)
    if method == "thompson":
        return thompson(s, n, rng)
    raise ValueError(f"unknown bandit method '{method}'; known: {', '.join(METHODS)}")


def thompson(s: np.ndarray, n: np.ndarray, rng: np.random.Generator) -> int:
    """Draw a success rate for each from its Beta posterior; take the best draw."""
    draws = rng.beta(PRIOR[0] + s, PRIOR[1] + n - s)
    return int(np.argmax(draws))


def ucb(s: np.ndarray, n: np.ndarray) -> int:
    """UCB1: an untried alternative first, then the best mean plus sqrt(2 ln N / n)."""
    untried = np.flatnonzero(n == 0)
    if untried.size:
        return int(untried[0])
    bonus = np.sqrt(2.0 * math.log(n.sum()) / n)
    return int(np.argmax(s / n + bonus))


def exploit(s: np.ndarray, n: np.ndarray) -> int:
    """The best posterior mean (ties: the first)."""
    return int(np.argmax(posterior_mean(s, n)))


def posterior_mean(s, n) -> np.ndarray:
    s, n = np.asarray(s, dtype=float), np.asarray(n, dtype=float)
    return (PRIOR[0] + s) / (PRIOR[0] + PRIOR[1] + n)


def below_share(n: np.ndarray, min_share: float) -> int | None:
    """The alternative furthest below `min_share` of all trials, or None."""
    if min_share <= 0 or n.size == 0:
        return None
    total = n.sum()
    shares = n / total if total else np.zeros_like(n)
    lacking = shares < min_share
    if not lacking.any():
        return None
    return int(np.argmin(np.where(lacking, shares, np.inf)))


def interval(successes: float, trials: float, level: float = 0.95) -> tuple[float, float]:
    """The equal-tailed credible interval of the success rate under the Beta posterior."""
    from scipy.stats import beta
    a, b = PRIOR[0] + successes, PRIOR[1] + trials - successes
    tail = (1.0 - level) / 2.0
    return float(beta.ppf(tail, a, b)), float(beta.ppf(1.0 - tail, a, b))
