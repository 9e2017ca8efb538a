"""The filter's fast lookups give what the plain ones give, to the bit: the likelihood field
read at every beam end of every particle (`FieldLookup.at_beams` against `beam_endpoints`
then the lookup), the blocked-cell lookup (`BlockedCells` against `GridMap.to_cells`,
`inside` and `free`), and the range march with the filter's kept cells or without them.
Whole runs are compared by `benchmarks/same_run.py`; these pin the pieces."""
from __future__ import annotations

import numpy as np

from skills.navigation.gridmap import GridMap
from skills.navigation.mcl import (BlockedCells, FieldLookup, beam_endpoints, expected_ranges,
                                   weighted_estimate)


def random_map(rng) -> GridMap:
    """40 x 60 cells of 0.05 m, a fifth occupied, some unknown, origin off zero."""
    occupied = rng.random((40, 60)) < 0.2
    unknown = rng.random((40, 60)) < 0.05
    return GridMap(occupied, 0.05, (-1.3, 0.7), unknown=unknown)


def test_at_beams_is_the_lookup_of_beam_endpoints():
    rng = np.random.default_rng(3)
    grid = random_map(rng)
    lookup = FieldLookup(grid, rng.normal(size=grid.shape), -7.5)
    for _ in range(20):
        particles = np.column_stack([rng.uniform(-2.0, 2.5, 300), rng.uniform(0.0, 3.5, 300),
                                     rng.uniform(-4.0, 4.0, 300)])
        beams = np.column_stack([rng.normal(0, 0.2, 36), rng.normal(0, 0.1, 36),
                                 rng.uniform(-np.pi, np.pi, 36)])
        ranges = rng.uniform(0.05, 6.0, 36)
        fast = lookup.at_beams(particles, beams, ranges)
        plain = lookup(*beam_endpoints(particles, beams, ranges))
        assert fast.tobytes() == plain.tobytes()
        turns = (np.cos(particles[:, 2]), np.sin(particles[:, 2]))   # as the filter keeps them
        assert lookup.at_beams(particles, beams, ranges, turns).tobytes() == plain.tobytes()


def test_the_estimate_with_the_kept_cosines_and_sines_is_the_estimate_without():
    rng = np.random.default_rng(6)
    for _ in range(20):
        particles = np.column_stack([rng.normal(1.0, 0.3, 500), rng.normal(-2.0, 0.3, 500),
                                     rng.normal(3.0, 0.4, 500)])
        weights = rng.random(500)
        weights /= weights.sum()
        pose, cov = weighted_estimate(particles, weights)
        kept = weighted_estimate(particles, weights,
                                 (np.cos(particles[:, 2]), np.sin(particles[:, 2])))
        assert kept[0] == pose and kept[1].tobytes() == cov.tobytes()


def test_blocked_cells_are_the_cells_not_known_free_on_and_off_the_map():
    rng = np.random.default_rng(4)
    grid = random_map(rng)
    cells = BlockedCells(grid)
    xs, ys = rng.uniform(-2.5, 3.0, 5000), rng.uniform(-0.5, 3.8, 5000)
    rows, cols = grid.to_cells(xs, ys)
    ok = grid.inside(rows, cols)
    expected = ~ok
    expected[ok] = ~grid.free[rows[ok], cols[ok]]
    assert (cells.at(xs, ys) == expected).all()
    assert expected.any() and (~expected).any() and (~ok).any()   # all three kinds were tried
    scratch_x, scratch_y = xs.copy(), ys.copy()
    assert (cells.at(scratch_x, scratch_y, scratch=True) == expected).all()


def test_the_march_with_kept_cells_is_the_march_without():
    rng = np.random.default_rng(5)
    grid = random_map(rng)
    cells = BlockedCells(grid)
    beams = np.column_stack([np.zeros(24), np.zeros(24), np.linspace(-np.pi, np.pi, 24)])
    for _ in range(10):
        pose = (rng.uniform(-1.0, 1.5), rng.uniform(1.0, 2.5), rng.uniform(-3.0, 3.0))
        kept = expected_ranges(grid, pose, beams, 4.0, cells=cells)
        assert kept.tobytes() == expected_ranges(grid, pose, beams, 4.0).tobytes()
