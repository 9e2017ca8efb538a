"""The laser's turn and advance between two scans (robots/scan_turn.py), on scans made here from
a known room: a rectangle 6 m x 4 m and a pillar, seen from a known pose and from a second pose
turned and moved by known amounts."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robots.scan_turn import motion_between

ANGLES = np.radians(np.arange(-135.0, 135.5, 1.0))           # 271 beams over 270 deg


def scan(x: float, y: float, th: float, noise: float = 0.01, seed: int = 0) -> np.ndarray:
    """Ranges from (x, y, th) in a room [-2, 4] x [-2, 2] with a pillar of radius 0.2 at (2, 1)."""
    rng = np.random.default_rng(seed)
    ranges = np.full(len(ANGLES), math.inf)
    for k, a in enumerate(ANGLES):
        dx, dy = math.cos(th + a), math.sin(th + a)
        hits = [t for t in ((4 - x) / dx if dx > 1e-9 else math.inf,
                            (-2 - x) / dx if dx < -1e-9 else math.inf,
                            (2 - y) / dy if dy > 1e-9 else math.inf,
                            (-2 - y) / dy if dy < -1e-9 else math.inf) if t > 0]
        px, py = 2 - x, 1 - y                                    # the pillar
        along = px * dx + py * dy
        miss = px * dy - py * dx
        if along > 0 and abs(miss) < 0.2:
            hits.append(along - math.sqrt(0.04 - miss * miss))
        ranges[k] = min(hits) + rng.normal(0.0, noise)
    return ranges


@pytest.mark.parametrize("turn_deg", [-5.4, -2.7, 0.0, 1.4, 2.7, 8.0])
def test_the_turn_between_two_scans_is_found(turn_deg):
    before = scan(0.0, 0.0, 0.0, seed=1)
    after = scan(0.0, 0.0, math.radians(turn_deg), seed=2)
    motion = motion_between(ANGLES, before, after)
    assert motion.trusted
    assert math.degrees(motion.turn) == pytest.approx(turn_deg, abs=0.1)
    assert motion.forward == pytest.approx(0.0, abs=0.006)


@pytest.mark.parametrize("metres", [-0.02, 0.0, 0.02, 0.04])
def test_the_advance_between_two_scans_is_found(metres):
    before = scan(0.0, 0.0, 0.0, seed=1)
    after = scan(metres, 0.0, 0.0, seed=2)
    motion = motion_between(ANGLES, before, after)
    assert motion.trusted
    assert motion.forward == pytest.approx(metres, abs=0.006)
    assert math.degrees(motion.turn) == pytest.approx(0.0, abs=0.1)


def test_scans_of_different_places_are_no_match():
    before = scan(0.0, 0.0, 0.0)
    elsewhere = np.full(len(ANGLES), 1.0) + np.sin(ANGLES * 7)      # nothing like the room
    assert not motion_between(ANGLES, before, elsewhere).trusted
    empty = np.full(len(ANGLES), math.inf)                          # no echoes at all
    assert not motion_between(ANGLES, before, empty).trusted
