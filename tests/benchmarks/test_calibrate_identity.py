"""The close-pass count that calibrates CONTINUITY (benchmarks/calibrate_identity.py): a pass
opens and closes as the follower's (`identity.contestants`), and ends kept, swapped or lost by
where the id that was on A is when it closes."""
from __future__ import annotations

import math

import numpy as np
import pytest

from skills.people.track import CONFIRMED, Track
from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def calibrate():
    with benchmark_script("calibrate_identity.py", "calibrate_identity") as module:
        yield module


def _track(tid, x, y):
    return Track(tid, x, y, 0.0, 0.0, np.eye(2) * 0.01, CONFIRMED, 0.0, 0.0, 0.0)


def _pass(calibrate, ids_after, a_walks_off=False):
    """B walks past A standing at (2, 0), 0.5 m off; the ids are (A's, B's) before and
    `ids_after` once B is past (with `a_walks_off`, A walks off while her track stays)."""
    counter = calibrate.PassCounter()
    for x in (4.0, 3.0, 2.4, 2.0, 1.6, 1.0, 0.0):
        a, b = (1, 2) if x > 2.0 else ids_after
        her = (2.0, 0.0) if x > 2.0 or not a_walks_off else (2.0, -2.0)
        people = {"A": her, "B": (x, 0.5)}
        tracks = [t for t in (_track(a, 2.0, 0.0), _track(b, x, 0.5)) if t.id is not None]
        counter.tick(tracks, people)
    return counter.outcomes


def test_a_close_pass_is_counted_kept_swapped_or_lost(calibrate):
    assert _pass(calibrate, (1, 2)) == ["kept"]
    assert _pass(calibrate, (2, 1)) == ["swapped"]
    assert _pass(calibrate, (None, 2)) == ["gone"]
    assert _pass(calibrate, (1, 2), a_walks_off=True) == ["astray"]    # left on a cart, say


def test_continuity_is_the_smoothed_log_odds_of_kept_to_swapped(calibrate):
    assert calibrate.continuity(0, 0) == 0.0
    assert math.isclose(calibrate.continuity(152, 6), math.log(153 / 7))


def test_scripted_passes_keep_the_bodies_clear(calibrate):
    rng = np.random.default_rng(0)
    for _ in range(200):
        g = calibrate.pass_geometry(rng)
        assert g["motion"] == "social" or calibrate._scripted_closest(g) >= 0.4
