"""The rest of the path in plain floats is the numpy version's to the bit (kept here verbatim),
including zero-length segments, vertices and the robot beyond either end."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from skills.navigation.navigation import Navigation, _unit


def old_rest_of_path(nav, x: float, y: float) -> np.ndarray:
    points = nav.plan.waypoints
    best, best_d, best_p = nav._segment, math.inf, points[nav._segment]
    for i in range(nav._segment, min(nav._segment + 3, len(points) - 1)):
        a, b = points[i], points[i + 1]
        ab = b - a
        t = float(np.clip(np.dot((x, y) - a, ab) / max(np.dot(ab, ab), 1e-12), 0.0, 1.0))
        q = a + t * ab
        d = math.hypot(x - q[0], y - q[1])
        if d < best_d - 1e-9:
            best, best_d, best_p = i, d, q
    nav._segment = best
    return np.vstack([best_p, points[best + 1:]])


def test_the_rest_of_the_path_in_floats_is_numpys():
    rng = np.random.default_rng(9)
    for _ in range(300):
        n = int(rng.integers(1, 9))
        waypoints = np.cumsum(rng.normal(0.0, 1.0, (n, 2)), axis=0)
        if n > 2:
            waypoints[2] = waypoints[1]                     # a zero-length segment
        segment = int(rng.integers(0, n))
        x, y = (waypoints[int(rng.integers(0, n))] + rng.normal(0.0, 0.5, 2) * rng.integers(0, 2)
                ).tolist()
        old = SimpleNamespace(plan=SimpleNamespace(waypoints=waypoints), _segment=segment)
        new = SimpleNamespace(plan=SimpleNamespace(waypoints=waypoints), _segment=segment)
        expected = old_rest_of_path(old, x, y)
        assert Navigation._rest_of_path(new, x, y).tobytes() == expected.tobytes()
        assert new._segment == old._segment


def test_unit_clamps_as_np_clip():
    for value in (-1.0, -0.0, 0.0, 0.3, 1.0, 1.5, math.inf, -math.inf, math.nan):
        expected = float(np.clip(value, 0.0, 1.0))
        got = _unit(value)
        assert (math.isnan(got) and math.isnan(expected)) or (
            got == expected and math.copysign(1.0, got) == math.copysign(1.0, expected))
