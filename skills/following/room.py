"""Where the robot fits: goals for following and searching must keep the robot's radius plus
a margin from walls and shelves (the navigation skill's grid map); without a map every place
fits. How far a person walks from one place to another (round shelves, not through them) is
`walking_distances`, on a coarse lattice of the map. A part of `Following`
(`skills.following.follower`).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

FREE_MARGIN = 0.1         # m beyond the robot's radius a goal must keep from walls
WALK_CELL = 0.25          # m: the lattice walking distances are measured on
PERSON_ROOM = 0.25        # m a person's centre keeps from walls (where a person fits)


class Room:
    """Free places near a point, towards a point, on her trail (a part of `Following`)."""

    def _free(self, x: float, y: float) -> bool:
        """The robot fits at (x, y) with a margin (True without a map)."""
        nav = self.navigation
        if nav is None:
            return True
        margin = nav.profile.radius + FREE_MARGIN
        return bool(nav.grid.clearance_at(x, y) >= margin)

    def _free_towards(self, start, end):
        """The point nearest `end` on the segment from `start` where the robot fits, walking
        back from `end` (a prediction that runs into a shelf stops before it); None if none."""
        for k in range(10, -1, -1):
            f = k / 10
            x, y = start[0] + f * (end[0] - start[0]), start[1] + f * (end[1] - start[1])
            if self._free(x, y):
                return x, y
        return None

    def _nearest_free(self, x: float, y: float):
        """The nearest point within 0.6 m of (x, y) where the robot fits (a customer walking
        close along a shelf), or None."""
        for r in (0.1, 0.2, 0.3, 0.45, 0.6):
            for k in range(12):
                a = k * math.pi / 6
                if self._free(x + r * math.cos(a), y + r * math.sin(a)):
                    return x + r * math.cos(a), y + r * math.sin(a)
        return None

    def _on_trail(self, cx: float, cy: float):
        """A point of the customer's own trail about `distance` behind them where the robot
        fits: where the straight line from the robot would cut a shelf corner."""
        back = 0.0
        prev = (cx, cy)
        for x, y in reversed(self._trail):
            back += math.hypot(prev[0] - x, prev[1] - y)
            prev = (x, y)
            if back >= self.params.distance and self._free(x, y):
                return x, y
        return None

    def _walking_from(self, start):
        """A function (x, y) -> metres a person walks from `start` to there (None where no
        way leads); None without a map (the straight line then)."""
        nav = self.navigation
        if nav is None:
            return None
        return walking_distances(nav.grid, start)


def walking_distances(grid, start):
    """(x, y) -> the walking distance from `start` on `grid` (8-connected lattice of WALK_CELL
    where a person fits, PERSON_ROOM from walls), None where no way leads there."""
    x0, y0, x1, y1 = grid.bounds
    xs = np.arange(x0 + WALK_CELL / 2, x1, WALK_CELL)
    ys = np.arange(y0 + WALK_CELL / 2, y1, WALK_CELL)
    gx, gy = np.meshgrid(xs, ys)
    free = grid.clearance(gx, gy) >= PERSON_ROOM
    rows, cols = free.shape
    index = np.arange(rows * cols).reshape(rows, cols)
    heads, tails, weights = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):     # each neighbour pair once
        r = slice(0, rows - dr)
        c = slice(max(0, -dc), cols - max(0, dc))
        r2 = slice(dr, rows)
        c2 = slice(max(0, dc), cols - max(0, -dc))
        both = free[r, c] & free[r2, c2]
        heads.append(index[r, c][both])
        tails.append(index[r2, c2][both])
        weights.append(np.full(int(both.sum()), WALK_CELL * math.hypot(dr, dc)))
    n = rows * cols
    graph = coo_matrix((np.concatenate(weights), (np.concatenate(heads),
                                                  np.concatenate(tails))), shape=(n, n)).tocsr()
    free_cells = np.flatnonzero(free)

    def nearest(x, y) -> int | None:
        if free_cells.size == 0:
            return None
        fx, fy = gx.ravel()[free_cells], gy.ravel()[free_cells]
        k = int(np.argmin((fx - x) ** 2 + (fy - y) ** 2))
        if math.hypot(fx[k] - x, fy[k] - y) > 1.0:
            return None
        return int(free_cells[k])

    source = nearest(*start)
    if source is None:
        return lambda x, y: math.hypot(x - start[0], y - start[1])
    far = dijkstra(graph, directed=False, indices=source)

    def walk(x: float, y: float) -> float | None:
        cell = nearest(x, y)
        if cell is None or not np.isfinite(far[cell]):
            return None
        return float(far[cell])

    return walk
