"""What a simulated person looks like to the camera: a colour histogram of their clothing.

Person followers tell people apart by appearance when positions cannot (two people passing
close, a shopper overtaking the robot and hiding the customer). A real camera pipeline crops
each detected person and reports a descriptor, most simply a normalised colour histogram of
the torso; here each person's histogram is drawn once from their id (a flat Dirichlet over
`BINS` bins: most pairs of people differ clearly, a few percent dress alike, as in a shop) and
every detection reports it with multiplicative log-normal noise (light, pose, the crop), drawn
from a stream of its own so that adding appearance changes no other random number of a run.
"""
from __future__ import annotations

import zlib

import numpy as np

BINS = 8
NOISE = 0.25        # standard deviation of the log of each bin's factor, per detection


def appearance_of(person_id: str) -> np.ndarray:
    """The person's true histogram: the same for the same id in every run."""
    rng = np.random.default_rng(zlib.crc32(person_id.encode("utf-8")))
    return rng.dirichlet(np.ones(BINS))


def observed(true: np.ndarray, rng: np.random.Generator) -> tuple[float, ...]:
    """One detection's histogram of a person who looks like `true`."""
    noisy = true * np.exp(rng.normal(0.0, NOISE, len(true)))
    return tuple(float(v) for v in noisy / noisy.sum())


def anyone(rng: np.random.Generator) -> tuple[float, ...]:
    """The histogram of a false positive (a poster, a coat on a rack): like nobody in particular."""
    return tuple(float(v) for v in rng.dirichlet(np.ones(BINS)))
