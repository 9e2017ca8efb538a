"""Comparing what people look like: the camera's colour histograms (`Track.appearance`).

The Hellinger distance between two normalised histograms, sqrt(1 - sum sqrt(p q)), is 0 for
the same histogram and 1 for histograms with nothing in common; it is the usual measure for
colour histograms in person tracking (Comaniciu et al.'s mean-shift tracker uses its
Bhattacharyya coefficient). With the simulated camera's noise, 99 % of two detections of the
same person lie within 0.19 of each other and 99 % of a detection and a person's average
within 0.14, while 95 % of pairs of different people lie beyond 0.25 (`SAME_PERSON` sits
between).
"""
from __future__ import annotations

import math

import numpy as np

SAME_PERSON = 0.2     # Hellinger distance up to which a detection looks like a known person


def distance(a, b) -> float:
    """Hellinger distance of two histograms of the same length (each sums to 1)."""
    p, q = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if p.shape != q.shape:
        raise ValueError(f"appearance histograms of {len(p)} and {len(q)} bins cannot be "
                         "compared; one detector must report one length")
    return math.sqrt(max(0.0, 1.0 - float(np.sum(np.sqrt(p * q)))))


def blend(model: np.ndarray | None, seen, weight: float) -> np.ndarray:
    """A running average of a person's look: `seen` mixed in at `weight` (the first one
    whole), renormalised."""
    seen = np.asarray(seen, dtype=float)
    mixed = seen if model is None else (1.0 - weight) * model + weight * seen
    return mixed / mixed.sum()
