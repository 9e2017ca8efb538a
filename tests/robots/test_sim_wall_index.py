"""The wall index answers exactly what a search over every wall answers, wherever it matters."""
import numpy as np
import pytest

from robots.sim import wall_index
from robots.sim.floor import load_floor
from robots.sim.wall_index import WallIndex


def full_search(positions, segments):
    """The nearest point of any segment, by measuring every one (the reference)."""
    best = np.empty_like(positions)
    for k, (x, y) in enumerate(positions):
        x1, y1, x2, y2 = segments.T
        ex, ey = x2 - x1, y2 - y1
        u = np.clip(((x - x1) * ex + (y - y1) * ey) / np.maximum(ex * ex + ey * ey, 1e-18), 0, 1)
        px, py = x1 + u * ex, y1 + u * ey
        i = int(np.argmin((px - x) ** 2 + (py - y) ** 2))
        best[k] = px[i], py[i]
    return best


def random_walls(rng, count):
    starts = rng.uniform(-10, 10, (count, 2))
    return np.hstack([starts, starts + rng.uniform(-3, 3, (count, 2))])


# the default, bucketed, and every wall searched (150 walls: above the default)
@pytest.mark.parametrize("few_walls", [wall_index.FEW_WALLS, 0, 10_000])
@pytest.mark.parametrize("seed", range(3))
def test_the_nearest_wall_within_reach_is_the_one_a_full_search_finds(monkeypatch, few_walls,
                                                                      seed):
    monkeypatch.setattr(wall_index, "FEW_WALLS", few_walls)
    rng = np.random.default_rng(seed)
    segments = random_walls(rng, 150)
    index = WallIndex(segments, reach=0.7)
    positions = rng.uniform(-16, 16, (4000, 2))       # some off the grid
    want = full_search(positions, segments)
    got = index.nearest_points(positions)
    near = np.hypot(*(positions - want).T) <= 0.7
    assert near.sum() > 500 and (~near).sum() > 500
    assert np.array_equal(got[near], want[near])
    assert (np.hypot(*(positions - got).T)[~near] > 0.7).all()


def test_a_floor_without_walls_has_every_wall_far_away():
    index = WallIndex(np.zeros((0, 4)), reach=0.7)
    assert (index.nearest_points(np.array([[0.0, 0.0]])) > 1e5).all()


def test_the_store_floor_is_answered_the_same_bucketed_or_not(monkeypatch):
    floor = load_floor("store")
    rng = np.random.default_rng(7)
    xmin, ymin, xmax, ymax = floor.bounds
    positions = rng.uniform([xmin, ymin], [xmax, ymax], (3000, 2))
    plain = WallIndex(floor.segments, reach=0.7).nearest_points(positions)
    monkeypatch.setattr(wall_index, "FEW_WALLS", 0)
    bucketed = WallIndex(floor.segments, reach=0.7).nearest_points(positions)
    near = np.hypot(*(positions - plain).T) <= 0.7
    assert near.any() and np.array_equal(plain[near], bucketed[near])


@pytest.mark.parametrize("seed", range(3))
def test_a_position_said_to_be_far_from_every_wall_is(seed):
    """A lower bound below a distance may say "perhaps" of a far position, never "no" of
    a near one."""
    rng = np.random.default_rng(seed)
    segments = random_walls(rng, 150)
    index = WallIndex(segments, reach=0.7)
    positions = rng.uniform(-16, 16, (4000, 2))
    true = np.hypot(*(positions - full_search(positions, segments)).T)
    for distance in (0.2, 0.7):
        near = index.lower_bounds(positions) < distance
        assert (near | (true >= distance)).all()
        assert (~near).sum() > 100                   # and it does rule some out


def test_a_few_positions_are_ruled_out_as_many_are():
    """`lower_bounds` answers a crowd's few positions (a plain loop) as it answers many
    (numpy), off the grid too."""
    rng = np.random.default_rng(5)
    index = WallIndex(random_walls(rng, 150), reach=0.7)
    positions = rng.uniform(-16, 16, (600, 2))
    assert len(positions) > wall_index.FEW_POSITIONS
    for distance in (0.2, 0.7):
        many = index.lower_bounds(positions) < distance
        few = np.concatenate([index.lower_bounds(positions[k:k + 7]) < distance
                              for k in range(0, len(positions), 7)])
        assert many.any() and (~many).any()
        assert np.array_equal(few, many)


@pytest.mark.parametrize("few_walls", [wall_index.FEW_WALLS, 10_000])
@pytest.mark.parametrize("seed", range(2))
def test_a_point_said_clear_of_walls_is_and_one_near_a_wall_is_not(monkeypatch, few_walls,
                                                                   seed):
    """`clear_of` (plain floats over the point's cell, the crowd's test for sparing a round of
    pushing apart) answers as a search over every wall, up to rounding, bucketed or not; and
    `lower_bounds` never exceeds a position's true distance."""
    monkeypatch.setattr(wall_index, "FEW_WALLS", few_walls)
    rng = np.random.default_rng(seed)
    segments = random_walls(rng, 150)
    index = WallIndex(segments, reach=0.7)
    positions = rng.uniform(-16, 16, (3000, 2))
    true = np.hypot(*(positions - full_search(positions, segments)).T)
    assert (index.lower_bounds(positions) <= true + 1e-9).all()
    for distance in (0.2, 0.5):
        clear = np.array([index.clear_of(x, y, distance) for x, y in positions.tolist()])
        decided = np.abs(true - distance) > 1e-9
        assert np.array_equal(clear[decided], (true >= distance)[decided])
        assert clear.any() and (~clear).any()
