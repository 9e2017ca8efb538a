"""The planner's CPU cuts change no bit: the window's graph is scipy's submatrix of the map's,
a line check answers as the code it replaced (kept here verbatim), and a windowed search finds
the same route as one on the whole map."""
from __future__ import annotations

import math

import numpy as np

from skills.navigation.costmap import cost_map
from skills.navigation.planner import (COST_WEIGHT, _build_graph, _cheap_line,
                                       _reduced_dijkstra, _room, _search_window, _window_graph)
from tests.skills.test_navigation_planner import RADIUS, RES, col, grid_of, room


def a_map():
    occupied = room(8.0, 5.0)
    occupied[: int(3.0 / RES), col(3.0)] = True               # a wall with a way round it
    occupied[int(2.0 / RES):, col(5.5)] = True
    occupied[int(1.0 / RES):int(1.6 / RES), col(1.5):col(2.2)] = True      # a pillar
    return cost_map(grid_of(occupied), RADIUS)


COSTMAP = a_map()
GRAPH = _build_graph(COSTMAP, COST_WEIGHT)


def test_the_windows_graph_is_the_maps_submatrix():
    rows, cols = COSTMAP.grid.shape
    rng = np.random.default_rng(4)
    for _ in range(30):
        r0, c0 = int(rng.integers(0, rows - 2)), int(rng.integers(0, cols - 2))
        window = (slice(r0, int(rng.integers(r0 + 1, rows + 1))),
                  slice(c0, int(rng.integers(c0 + 1, cols + 1))))
        r, c = np.mgrid[window[0], window[1]]
        nodes = (r * cols + c).ravel()
        data, indices, indptr = _window_graph(GRAPH.matrix, window, nodes, cols)
        expected = GRAPH.matrix[nodes][:, nodes].tocsr()
        expected.sort_indices()
        assert np.array_equal(indptr, expected.indptr)
        assert np.array_equal(indices, expected.indices)
        assert data.tobytes() == expected.data.tobytes()


def old_cheap_line(costmap, a, b, budget, cost_weight, least=-math.inf):
    span = max(abs(int(b[0]) - int(a[0])), abs(int(b[1]) - int(a[1])))
    t = np.linspace(0.0, 1.0, 2 * span + 1)
    r = np.rint(a[0] + t * (b[0] - a[0])).astype(int)
    c = np.rint(a[1] + t * (b[1] - a[1])).astype(int)
    if costmap.lethal[r, c].any():
        return False
    if _room(costmap, r, c).min() < least:
        return False
    length = costmap.grid.resolution * math.hypot(int(b[0]) - int(a[0]), int(b[1]) - int(a[1]))
    return length * (1.0 + cost_weight * float(costmap.cost[r, c].mean())) <= budget


def test_a_line_check_answers_as_before():
    rows, cols = COSTMAP.grid.shape
    rng = np.random.default_rng(5)
    answers = set()
    for _ in range(400):
        a = np.array([rng.integers(0, rows), rng.integers(0, cols)])
        b = np.array([rng.integers(0, rows), rng.integers(0, cols)])
        length = RES * math.hypot(*(b - a))
        budget = length * float(rng.uniform(1.0, 3.0))
        least = float(rng.uniform(0.0, 0.5))
        old = old_cheap_line(COSTMAP, a, b, budget, COST_WEIGHT, least)
        assert _cheap_line(COSTMAP, a, b, budget, COST_WEIGHT, least) == old
        answers.add(old)
    assert answers == {True, False}


def test_a_windowed_search_finds_the_whole_maps_route():
    shape, cols = COSTMAP.grid.shape, COSTMAP.grid.shape[1]
    free = np.flatnonzero(~COSTMAP.lethal.ravel())
    rng = np.random.default_rng(6)
    found = 0
    for _ in range(25):
        source, target = (int(v) for v in rng.choice(free, 2, replace=False))
        sr, sc = divmod(source, cols)
        tr, tc = divmod(target, cols)
        h = RES * max(abs(sr - tr), abs(sc - tc))
        limit = 2.0 * h + 1.0
        window = _search_window((sr, sc), (tr, tc), (limit + 2 * h) / RES, shape)
        whole = _reduced_dijkstra(GRAPH, None, source, target, shape, RES, limit)
        part = _reduced_dijkstra(GRAPH, window, source, target, shape, RES, limit)
        assert whole[0] == part[0]
        if whole[1] is None:
            assert part[1] is None
            continue
        found += 1
        assert whole[1].tobytes() == part[1].tobytes()
        assert whole[1][0] == source and whole[1][-1] == target
    assert found >= 10
