"""Where simulated people can walk, and the way between two points around walls and shelves.

People of `shop`, `lead` and routed `walk`/`leave` steps do not walk through shelves: they take
the shortest way on a grid of cells whose centres keep `clearance` from every wall (Dijkstra
from the goal, over 8 neighbours, with scipy's sparse graph routines), shortened by pulling
the string wherever the straight line between two points keeps that clearance too. The grid is
built once per floor and the search once per goal cell; both are cached.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from robots.sim.floor import Floor

CELL = 0.1                 # m
CLEARANCE = 0.3            # m from a person's centre to any wall (body radius 0.2 + margin)
_GOAL_CACHE = 64           # searches kept per grid
_LINE_CACHE = 4096         # answers of `clear` kept per grid
_PULL_BATCH = 16           # lines from one anchor tested together when pulling the string
_GRIDS: dict[tuple, "WalkGrid"] = {}


class WalkGrid:
    """Free cells of a floor for a person's centre, and shortest ways between points."""

    def __init__(self, floor: Floor, cell: float = CELL, clearance: float = CLEARANCE) -> None:
        self.cell = cell
        self.clearance = clearance
        xmin, ymin, xmax, ymax = floor.bounds
        self.origin = (xmin, ymin)
        self.cols = max(1, int(math.ceil((xmax - xmin) / cell)))
        self.rows = max(1, int(math.ceil((ymax - ymin) / cell)))
        xs = xmin + (np.arange(self.cols) + 0.5) * cell
        ys = ymin + (np.arange(self.rows) + 0.5) * cell
        gx, gy = np.meshgrid(xs, ys)
        self.free = _wall_distance(gx.ravel(), gy.ravel(), floor.segments) >= clearance
        self.free = self.free.reshape(self.rows, self.cols)
        self.free.flags.writeable = False       # the caches below rest on it
        self._free_cells = np.nonzero(self.free)
        self._nearest: dict[tuple[int, int], int | None] = {}
        self._graph = self._build_graph()
        self._searches: dict[int, np.ndarray] = {}
        self._fractions: dict[int, np.ndarray] = {}     # samples -> linspace(0, 1)
        self._lines: dict[tuple, bool] = {}               # (ax, ay, bx, by) -> clear

    def route(self, start: tuple[float, float], goal: tuple[float, float]
              ) -> list[tuple[float, float]]:
        """Points to walk through from `start` to `goal` (goal last, start left out). Without
        a way (start or goal walled in) the straight line: people are never stuck."""
        if self.clear(start, goal):
            return [goal]
        a, b = self._nearest_free(start), self._nearest_free(goal)
        if a is None or b is None:
            return [goal]
        predecessors = self._search(b)
        if a != b and predecessors[a] < 0:
            return [goal]
        cells = [a]
        while cells[-1] != b:
            cells.append(int(predecessors[cells[-1]]))
        points = [self._centre(c) for c in cells[1:-1]] + [goal]
        return self._pull_string(start, points)

    def clear(self, a: tuple[float, float], b: tuple[float, float]) -> bool:
        """True when every point of the straight line a–b lies in a free cell. Kept per
        line (the grid does not change): a shopper held up asks about the same line, from
        where they stand to their path's next point, every substep."""
        key = (a[0], a[1], b[0], b[1])
        known = self._lines.get(key)
        if known is None:
            known = self._clear(a, b)
            if len(self._lines) >= _LINE_CACHE:
                self._lines.clear()
            self._lines[key] = known
        return known

    def _clear(self, a: tuple[float, float], b: tuple[float, float]) -> bool:
        s = self._samples(a, b)
        rows, cols = self._cells(a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]))
        inside = (rows >= 0) & (rows < self.rows) & (cols >= 0) & (cols < self.cols)
        return bool(inside.all() and self.free[rows, cols].all())

    def clear_run(self, a: tuple[float, float], points: list) -> int:
        """How many of `points`, in order, `clear` finds reachable from `a` before the first
        it does not: `clear`'s samples and arithmetic for all of them in one pass (the
        string pulling asks for a hundred lines per route, one numpy pass each before)."""
        fractions, along_x, along_y = [], [], []
        for b in points:
            fractions.append(self._samples(a, b))
            along_x.append(b[0] - a[0])
            along_y.append(b[1] - a[1])
        counts = [len(f) for f in fractions]
        s = np.concatenate(fractions)
        rows, cols = self._cells(a[0] + s * np.repeat(along_x, counts),
                                 a[1] + s * np.repeat(along_y, counts))
        ok = (rows >= 0) & (rows < self.rows) & (cols >= 0) & (cols < self.cols)
        ok[ok] = self.free[rows[ok], cols[ok]]
        starts = np.cumsum([0] + counts[:-1])
        blocked = np.flatnonzero(~np.logical_and.reduceat(ok, starts))
        return int(blocked[0]) if len(blocked) else len(points)

    # -- helpers ---------------------------------------------------------------------------

    def _samples(self, a: tuple[float, float], b: tuple[float, float]) -> np.ndarray:
        """The fractions of the line a–b at which `clear` looks: every half cell or closer."""
        length = math.hypot(b[0] - a[0], b[1] - a[1])
        samples = max(2, int(length / (self.cell / 2)) + 2)
        s = self._fractions.get(samples)
        if s is None:                       # the same few counts come back all the time
            s = self._fractions[samples] = np.linspace(0.0, 1.0, samples)
        return s

    def _cells(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        cols = np.floor((np.asarray(x) - self.origin[0]) / self.cell).astype(int)
        rows = np.floor((np.asarray(y) - self.origin[1]) / self.cell).astype(int)
        return rows, cols

    def _centre(self, index: int) -> tuple[float, float]:
        row, col = divmod(index, self.cols)
        return (self.origin[0] + (col + 0.5) * self.cell, self.origin[1] + (row + 0.5) * self.cell)

    def _nearest_free(self, point: tuple[float, float]) -> int | None:
        """Index of the free cell nearest to the point (the point's own cell when free).
        Kept per cell: people standing at a shelf ask for the same walled-in cell every
        substep, and the search runs over every free cell of the floor."""
        rows, cols = self._cells(point[0], point[1])
        row, col = int(rows), int(cols)
        if 0 <= row < self.rows and 0 <= col < self.cols and self.free[row, col]:
            return row * self.cols + col
        if (row, col) not in self._nearest:
            self._nearest[(row, col)] = self._search_nearest_free(row, col)
        return self._nearest[(row, col)]

    def _search_nearest_free(self, row: int, col: int) -> int | None:
        free_rows, free_cols = self._free_cells
        if free_rows.size == 0:
            return None
        nearest = int(np.argmin((free_rows - row) ** 2 + (free_cols - col) ** 2))
        return int(free_rows[nearest]) * self.cols + int(free_cols[nearest])

    def _build_graph(self):
        """Sparse graph of free cells to their free 8 neighbours (edge length in m)."""
        index = np.arange(self.rows * self.cols).reshape(self.rows, self.cols)
        sources, targets, weights = [], [], []
        for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
            r0, r1 = max(0, -dr), self.rows - max(0, dr)
            c0, c1 = max(0, -dc), self.cols - max(0, dc)
            here = self.free[r0:r1, c0:c1]
            there = self.free[r0 + dr:r1 + dr, c0 + dc:c1 + dc]
            both = here & there
            if dr and dc:       # diagonal: both side cells free, so no corner is cut
                both &= self.free[r0 + dr:r1 + dr, c0:c1] & self.free[r0:r1, c0 + dc:c1 + dc]
            sources.append(index[r0:r1, c0:c1][both])
            targets.append(index[r0 + dr:r1 + dr, c0 + dc:c1 + dc][both])
            weights.append(np.full(int(both.sum()), math.hypot(dr, dc) * self.cell))
        size = self.rows * self.cols
        return coo_matrix((np.concatenate(weights),
                           (np.concatenate(sources), np.concatenate(targets))),
                          shape=(size, size)).tocsr()

    def _search(self, goal: int) -> np.ndarray:
        """Predecessors towards `goal` for every cell (-9999 where unreachable)."""
        found = self._searches.get(goal)
        if found is None:
            _, found = dijkstra(self._graph, directed=False, indices=goal,
                                return_predecessors=True)
            if len(self._searches) >= _GOAL_CACHE:
                self._searches.pop(next(iter(self._searches)))
            self._searches[goal] = found
        return found

    def _pull_string(self, start, points: list) -> list[tuple[float, float]]:
        """Drop the points the straight line can skip while keeping the clearance."""
        out, anchor, i = [], start, 0
        while i < len(points):
            j = i
            while j + 1 < len(points):       # as far as the line from the anchor stays clear
                batch = points[j + 1:j + 1 + _PULL_BATCH]
                reached = self.clear_run(anchor, batch)
                j += reached
                if reached < len(batch):
                    break
            out.append(points[j])
            anchor, i = points[j], j + 1
        return out


def walk_grid(floor: Floor) -> WalkGrid:
    """The (cached) walk grid of a floor."""
    key = (floor.name, floor.segments.tobytes())
    grid = _GRIDS.get(key)
    if grid is None:
        grid = _GRIDS[key] = WalkGrid(floor)
    return grid


def _wall_distance(x: np.ndarray, y: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distance from each point to the nearest segment, in chunks of segments."""
    best = np.full(x.shape, np.inf)
    for x1, y1, x2, y2 in segments:
        ex, ey = x2 - x1, y2 - y1
        u = np.clip(((x - x1) * ex + (y - y1) * ey) / (ex * ex + ey * ey), 0.0, 1.0)
        best = np.minimum(best, np.hypot(x1 + u * ex - x, y1 + u * ey - y))
    return best


__all__ = ["WalkGrid", "walk_grid"]
