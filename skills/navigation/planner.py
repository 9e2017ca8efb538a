"""The global planner: the cheapest 8-connected path on the cost map, then shortened.

The search is A*, run as scipy's compiled Dijkstra (`csgraph`) on edge costs reduced by an octile
heuristic and bounded by a growing distance limit (see `_astar`): optimal, and several times
faster than a Python A* on the office map's ~100 000 cells. Each edge costs its length times
(1 + `cost_weight` × the mean cell cost of its ends), so paths keep to the middle of a hallway
and pass a door centred. The graph is built once per cost map (vectorised) and cached.

The cell path is then shortened by string pulling: a waypoint is dropped when the straight line
that replaces it crosses no lethal cell and costs no more than the stretch of path it replaces
(within 5 % and a cell, the discretisation), and, within `TIGHT` of the lethal edge, comes no
closer to a wall than that stretch does: so the robot drives straight lines without trading the
search's distance from walls for them, and enters a narrow door along it rather than across
its jamb (a line cut past a jamb left a round robot no way forward). A start or goal just inside the inflation (the robot parked near a wall, a
place drawn close to one) is snapped to the nearest free cell within `snap_distance`.
"""
from __future__ import annotations

import functools
import math
import weakref
from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components, dijkstra

from skills.navigation.costmap import CostMap

# why a plan failed: the first words of `Plan.reason`
GOAL_OUTSIDE = "goal outside the map"
GOAL_IN_WALL = "goal in a wall"
START_OUTSIDE = "start outside the map"
START_BLOCKED = "start blocked"
UNREACHABLE = "goal unreachable"

COST_WEIGHT = 3.0
SHORTCUT_SLACK = 0.05       # a shortcut may cost this fraction (plus a cell) more than the path
SNAP_DISTANCE = 0.3          # m a blocked start or goal may be moved to the nearest free cell
TIGHT = 0.2                  # m beyond the lethal edge within which a shortcut keeps its distance
_STEPS = ((0, 1), (1, 0), (1, 1), (1, -1))      # the other four follow by symmetry

_graphs: "weakref.WeakKeyDictionary[CostMap, dict]" = weakref.WeakKeyDictionary()


@dataclass(frozen=True)
class Plan:
    """Waypoints (n, 2) in metres from start to goal; empty, with a reason, when there is none."""
    waypoints: np.ndarray
    length: float = math.inf               # m along the waypoints
    reason: str = ""                       # '' when found; else starts with one of the codes
    start: tuple[float, float] | None = None   # where the search started (after snapping)
    goal: tuple[float, float] | None = None
    cells: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=int), repr=False)

    @property
    def found(self) -> bool:
        return not self.reason


def _no_path(reason: str) -> Plan:
    return Plan(np.zeros((0, 2)), math.inf, reason)


class GlobalPlanner:
    def __init__(self, costmap: CostMap, *, cost_weight: float = COST_WEIGHT,
                 snap_distance: float = SNAP_DISTANCE) -> None:
        self.costmap = costmap
        self.cost_weight = float(cost_weight)
        self.snap_distance = float(snap_distance)

    def plan(self, start, goal, costmap: CostMap | None = None) -> Plan:
        """A path from `start` (x, y) to `goal` (x, y) on `costmap` (default: the planner's)."""
        costmap = costmap or self.costmap
        grid = costmap.grid
        s = self._endpoint(costmap, start, "start")
        if isinstance(s, str):
            return _no_path(s)
        g = self._endpoint(costmap, goal, "goal")
        if isinstance(g, str):
            return _no_path(g)
        cols = grid.shape[1]
        graph = self._graph(costmap)
        source, target = s[0] * cols + s[1], g[0] * cols + g[1]
        if source == target:
            cells = np.array([s])
        else:
            dist, route = _astar(graph, source, target, grid.shape, grid.resolution)
            if not math.isfinite(dist):
                return _no_path(f"{UNREACHABLE}: no way from ({start[0]:.2f}, {start[1]:.2f}) to "
                                f"({goal[0]:.2f}, {goal[1]:.2f}) on map '{grid.name}' for a "
                                f"robot of radius {costmap.radius:.2f} m (walls or obstacles "
                                "close it off)")
            cells = np.column_stack([route // cols, route % cols])
        keep = _shortcut(costmap, cells, self.cost_weight)
        xs, ys = grid.to_world(cells[keep, 0], cells[keep, 1])
        points = np.column_stack([xs, ys])
        points[0] = start[:2]
        points[-1] = goal[:2] if not costmap.lethal_at(goal[0], goal[1]) else points[-1]
        if len(points) == 1:
            points = np.vstack([points, points])
        length = float(np.hypot(*np.diff(points, axis=0).T).sum())
        sx, sy = grid.to_world(s[0], s[1])
        gx, gy = grid.to_world(g[0], g[1])
        return Plan(points, length, "", (float(sx), float(sy)), (float(gx), float(gy)), cells)

    def _endpoint(self, costmap: CostMap, point, what: str):
        """The (row, col) to search from or to, snapped off the inflation; or why there is none."""
        grid = costmap.grid
        x, y = float(point[0]), float(point[1])
        if not (math.isfinite(x) and math.isfinite(y)):
            return f"{GOAL_OUTSIDE if what == 'goal' else START_OUTSIDE}: ({x}, {y}) is not a point"
        r, c = (int(v) for v in grid.to_cells(x, y))
        if not grid.inside(r, c):
            xmin, ymin, xmax, ymax = grid.bounds
            code = GOAL_OUTSIDE if what == "goal" else START_OUTSIDE
            return (f"{code}: ({x:.2f}, {y:.2f}) is outside map '{grid.name}' "
                    f"(x {xmin:.2f} … {xmax:.2f}, y {ymin:.2f} … {ymax:.2f})")
        if not costmap.lethal[r, c]:
            return r, c
        if grid.occupied[r, c]:
            code = GOAL_IN_WALL if what == "goal" else START_BLOCKED
            return f"{code}: ({x:.2f}, {y:.2f}) is inside a wall or obstacle of map '{grid.name}'"
        rows, cols = costmap.nearest_free
        fr, fc = int(rows[r, c]), int(cols[r, c])
        distance = math.hypot(fr - r, fc - c) * grid.resolution
        if not costmap.lethal[fr, fc] and distance <= self.snap_distance:
            return fr, fc
        code = GOAL_IN_WALL if what == "goal" else START_BLOCKED
        if grid.unknown is not None and grid.unknown[r, c]:
            why = "is in an unknown part of the map"
        else:
            why = f"is closer to a wall than the robot's radius {costmap.radius:.2f} m"
        nearest = (f"; the nearest spot the robot fits is {distance:.2f} m away"
                   if not costmap.lethal[fr, fc] else "")
        return f"{code}: ({x:.2f}, {y:.2f}) {why}{nearest}"

    def _graph(self, costmap: CostMap) -> "_Graph":
        per_map = _graphs.setdefault(costmap, {})
        if self.cost_weight not in per_map:
            per_map[self.cost_weight] = _build_graph(costmap, self.cost_weight)
        return per_map[self.cost_weight]


@dataclass(frozen=True)
class _Graph:
    """The search graph in CSR form, with each node's connected component (a goal in another
    one is unreachable without a search)."""
    matrix: csr_matrix
    components: np.ndarray


def _astar(graph: _Graph, source: int, target: int, shape: tuple[int, int],
           resolution: float) -> tuple[float, np.ndarray | None]:
    """A* as Dijkstra on reduced costs w(u, v) - h(u) + h(v), with h the octile distance to the
    target (consistent: no edge is cheaper than its length). scipy's Dijkstra cannot stop at the
    target, but with a distance `limit` it only settles the nodes whose reduced distance is
    below it, which is the A* search region; the limit doubles until the target is inside.
    Returns the true cost to the target (inf when unreachable) and the nodes from source to
    target (None when unreachable).

    Each bounded search runs on the window of the grid that holds every node it can reach
    (`_search_window`), not on the whole map: re-weighting a store's 1.7 million edges cost ten
    times the search itself, and the follower plans several times a second."""
    if graph.components[source] != graph.components[target]:
        return math.inf, None      # the searches below would end on the whole map, in vain
    rows, cols = shape
    sr, sc = divmod(source, cols)
    tr, tc = divmod(target, cols)
    h_source = resolution * _octile(abs(sr - tr), abs(sc - tc))
    limit = 0.5 * h_source + 1.0
    while limit < 4.0 * h_source + 50.0:
        window = _search_window((sr, sc), (tr, tc), (limit + h_source) / resolution, shape)
        if _size(window) > rows * cols / 4:      # cutting it out would cost more than it saves
            window = None
        dist, route = _reduced_dijkstra(graph, window, source, target, shape, resolution, limit)
        if math.isfinite(dist):
            return dist, route
        limit *= 2.0
    return _reduced_dijkstra(graph, None, source, target, shape, resolution, np.inf)


def _window_graph(matrix: csr_matrix, window, nodes: np.ndarray, cols: int):
    """The edges among the window's nodes, renumbered row-major within it, in CSR order, as
    (data, indices, indptr). A rectangle of a row-major grid: each of its rows is a run of
    consecutive nodes, whose edges are a run too (one slice per row, not a gather per edge),
    and those leaving the window are dropped, which scipy's general column indexing does many
    times slower. An edge ends at most a row and a column beyond its start, so a table of the
    local numbers over the window's rows and one more each side renumbers their ends (-1:
    outside the window)."""
    indptr = matrix.indptr
    width = window[1].stop - window[1].start
    first = nodes[::width]
    runs = list(zip(indptr[first].tolist(), indptr[first + width].tolist()))
    data = np.concatenate([matrix.data[a:b] for a, b in runs])
    ends = np.concatenate([matrix.indices[a:b] for a, b in runs])
    base = max(0, int(first[0]) - cols - 1)
    table = np.full(min(int(nodes[-1]) + cols + 2, len(indptr) - 1) - base, -1,
                    dtype=matrix.indices.dtype)
    table[nodes - base] = np.arange(len(nodes))
    ends -= base
    local = table[ends]
    inside = local >= 0
    # edges kept before each node's first: the count of kept edges up to its offset
    kept = np.concatenate(([0], np.cumsum(inside)))
    offsets = np.concatenate(([0], np.cumsum(indptr[nodes + 1] - indptr[nodes])))
    return data[inside], local[inside], kept[offsets]


def _size(window: tuple[slice, slice]) -> int:
    return (window[0].stop - window[0].start) * (window[1].stop - window[1].start)


def _octile(dr, dc):
    """Cells of the shortest 8-connected way across dr rows and dc columns (in steps of one)."""
    return np.maximum(dr, dc) + (math.sqrt(2) - 1) * np.minimum(dr, dc)


def _search_window(source, target, reach: float, shape) -> tuple[slice, slice]:
    """The rows and columns a search bounded by `limit` can reach, with reach = (limit +
    h(source)) in cells. A node v it settles or even queues has g(v) + h(v) - h(source) <=
    limit, and g and h are at least the octile distances, which are at least the per-axis
    distances: so |v - s| + |v - t| <= reach along each axis. Two cells of margin."""
    rows, cols = shape
    (sr, sc), (tr, tc) = source, target
    low_r, high_r = (sr + tr - reach) / 2 - 2, (sr + tr + reach) / 2 + 2
    low_c, high_c = (sc + tc - reach) / 2 - 2, (sc + tc + reach) / 2 + 2
    return (slice(max(0, math.floor(low_r)), min(rows, math.ceil(high_r) + 1)),
            slice(max(0, math.floor(low_c)), min(cols, math.ceil(high_c) + 1)))


def _reduced_dijkstra(graph: _Graph, window, source: int, target: int, shape,
                      resolution: float, limit: float) -> tuple[float, np.ndarray | None]:
    """One bounded Dijkstra on reduced costs, on the window's nodes (None: the whole map).

    The window's nodes keep their order (row-major in both), every edge among them keeps its
    weight, and no node outside it can be reached within the limit: so the search visits the
    same nodes in the same order as on the whole map and finds the same predecessors. Returns
    the cost and the nodes (the map's numbers) from source to target; None beyond the limit."""
    rows, cols = shape
    tr, tc = divmod(target, cols)
    if window is None:
        nodes = None
        matrix = graph.matrix
        data, indices, indptr = matrix.data, matrix.indices, matrix.indptr
        r, c = np.divmod(np.arange(rows * cols), cols)
    else:
        rows_range = np.arange(window[0].start, window[0].stop)
        cols_range = np.arange(window[1].start, window[1].stop)
        r, c = np.repeat(rows_range, len(cols_range)), np.tile(cols_range, len(rows_range))
        nodes = r * cols + c
        data, indices, indptr = _window_graph(graph.matrix, window, nodes, cols)
    size = len(indptr) - 1
    h = resolution * _octile(np.abs(r - tr), np.abs(c - tc))
    # each edge's start's h: h repeated over the node's edges (h[start] of every edge)
    reduced = np.maximum(data - np.repeat(h, np.diff(indptr)) + h[indices], 1e-12)
    weighted = csr_matrix((reduced, indices, indptr), shape=(size, size), copy=False)
    local_source = source if nodes is None else int(np.searchsorted(nodes, source))
    local_target = target if nodes is None else int(np.searchsorted(nodes, target))
    dist, pred = dijkstra(weighted, indices=local_source, return_predecessors=True,
                          limit=limit)
    cost = float(dist[local_target] + h[local_source])
    if not math.isfinite(cost):
        return cost, None
    route = _trace(pred, local_source, local_target)
    return cost, route if nodes is None else nodes[route]


def _build_graph(costmap: CostMap, cost_weight: float) -> _Graph:
    """Edges between 8-neighbouring non-lethal cells, both ways, weighted by length and cost."""
    rows, cols = costmap.lethal.shape
    index = np.arange(rows * cols).reshape(rows, cols)
    ok = ~costmap.lethal
    cost = costmap.cost
    res = costmap.grid.resolution
    heads, tails, weights = [], [], []
    for dr, dc in _STEPS:
        a = (slice(0, rows - dr), slice(max(0, -dc), cols - max(0, dc)))
        b = (slice(dr, rows), slice(max(0, dc), cols + min(0, dc) or None))
        both = ok[a] & ok[b]
        w = res * math.hypot(dr, dc) * (1.0 + cost_weight * 0.5 * (cost[a] + cost[b]))[both]
        ia, ib = index[a][both], index[b][both]
        heads += [ia, ib]
        tails += [ib, ia]
        weights += [w, w]
    matrix = csr_matrix((np.concatenate(weights), (np.concatenate(heads), np.concatenate(tails))),
                        shape=(rows * cols, rows * cols))
    matrix.sort_indices()
    _, components = connected_components(matrix, directed=False)
    return _Graph(matrix, components)


def _trace(pred: np.ndarray, source: int, target: int) -> np.ndarray:
    """The nodes from source to target by following the predecessors back."""
    chain = [target]
    node = target
    while node != source:
        node = int(pred[node])
        chain.append(node)
    return np.array(chain[::-1])


def _shortcut(costmap: CostMap, cells: np.ndarray, cost_weight: float) -> list[int]:
    """Indices of the cells to keep as waypoints (string pulling, cost-aware).

    A straight line replaces a stretch of the path when it crosses no lethal cell and costs no
    more than the stretch (length × (1 + weight × cell cost), as in the search), within slack.
    From each kept cell the farthest such line is found by galloping then bisecting (a few
    line checks per waypoint instead of one per cell)."""
    n = len(cells)
    if n <= 2:
        return list(range(n))
    res = costmap.grid.resolution
    cost = costmap.cost[cells[:, 0], cells[:, 1]]
    step = res * np.hypot(*np.diff(cells, axis=0).T)
    along = np.concatenate([[0.0], np.cumsum(step * (1.0 + cost_weight * 0.5 * (cost[1:] + cost[:-1])))])
    room = _room(costmap, cells[:, 0], cells[:, 1])

    def cheap(a: int, b: int) -> bool:
        budget = (along[b] - along[a]) * (1.0 + SHORTCUT_SLACK) + res
        least = float(room[a:b + 1].min()) - res / 2
        return _cheap_line(costmap, cells[a], cells[b], budget, cost_weight, least)

    keep = [0]
    anchor = 0
    while anchor < n - 1:
        good, jump = anchor + 1, 1                 # the next cell is always reachable
        while good + jump < n and cheap(anchor, good + jump):
            good += jump
            jump *= 2
        bad = min(good + jump, n)                  # first index known (or assumed) not cheap
        while bad - good > 1:
            middle = (good + bad) // 2
            if cheap(anchor, middle):
                good = middle
            else:
                bad = middle
        keep.append(good)
        anchor = good
    return keep


def _room(costmap: CostMap, rows, cols) -> np.ndarray:
    """Distance to walls at cells, counted only up to `TIGHT` beyond the bounding radius."""
    return np.minimum(costmap.clearance[rows, cols], costmap.radius + TIGHT)


def _cheap_line(costmap: CostMap, a: np.ndarray, b: np.ndarray, budget: float,
                cost_weight: float, least: float = -math.inf) -> bool:
    """The straight line between two cells crosses no lethal cell, costs at most `budget` and
    keeps at least `least` m of `_room` everywhere."""
    span = max(abs(int(b[0]) - int(a[0])), abs(int(b[1]) - int(a[1])))
    t = _unit_steps(2 * span + 1)
    r = np.rint(a[0] + t * (b[0] - a[0])).astype(int)
    c = np.rint(a[1] + t * (b[1] - a[1])).astype(int)
    cells = r * costmap.lethal.shape[1] + c         # flat: cheaper than 2-D fancy indexing
    if costmap.lethal.ravel()[cells].any():
        return False
    # _room's least: the least clearance, capped as _room caps each cell
    if min(costmap.clearance.ravel()[cells].min(), costmap.radius + TIGHT) < least:
        return False
    length = costmap.grid.resolution * math.hypot(int(b[0]) - int(a[0]), int(b[1]) - int(a[1]))
    return length * (1.0 + cost_weight * float(costmap.cost.ravel()[cells].mean())) <= budget


@functools.lru_cache(maxsize=512)
def _unit_steps(count: int) -> np.ndarray:
    """np.linspace(0, 1, count), made once per count (read-only)."""
    steps = np.linspace(0.0, 1.0, count)
    steps.flags.writeable = False
    return steps


def path_length(points: np.ndarray) -> float:
    """Metres along a polyline (n, 2)."""
    points = np.asarray(points, dtype=float)
    if len(points) < 2:
        return 0.0
    return float(np.hypot(*np.diff(points, axis=0).T).sum())
