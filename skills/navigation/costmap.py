"""The inflated cost map the planner searches: walls grown by the robot's radius, plus a band of
decaying cost beyond it so paths keep away from walls where there is room.

A cell is *lethal* when the robot's centre there would put its body within reach of a wall
(distance to the nearest occupied cell centre below radius + half a cell, since a wall may lie
anywhere in its cell). For a footprint that is not round that radius is the *inscribed* one
(no orientation fits closer), and the band up to the circumscribed radius costs the most a
free cell can (the robot fits there only turned along the way: passable, avoided where there
is room), as in Nav2's inflation layer. Beyond that, cost falls off exponentially over `band`
metres. Unknown cells (a SLAM map's unexplored parts) are lethal unless
`unknown_cost` allows them. Cost maps are cached per map and parameters.
"""
from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy import ndimage

from skills.navigation.footprint import Footprint
from skills.navigation.gridmap import GridMap

INFLATION_BAND = 0.6        # m beyond the lethal radius over which cost decays
DECAY = 0.2                 # m: cost falls by a factor e every DECAY metres

_cache: "weakref.WeakKeyDictionary[GridMap, dict]" = weakref.WeakKeyDictionary()


@dataclass(frozen=True, eq=False)
class CostMap:
    """Per cell: `lethal` (bool) and `cost` in [0, 1] (1 at the lethal edge, 0 far from walls)."""
    grid: GridMap
    radius: float              # m, the robot's bounding radius
    band: float
    decay: float
    unknown_cost: float | None
    lethal: np.ndarray
    cost: np.ndarray
    clearance: np.ndarray      # m from each cell centre to the nearest occupied cell centre
    inscribed: float | None = None   # m, the lethal radius when smaller than `radius`

    @cached_property
    def nearest_free(self) -> tuple[np.ndarray, np.ndarray]:
        """For every cell, the (row, col) of the nearest non-lethal cell (snapping start/goal)."""
        if self.lethal.all():
            rows, cols = np.indices(self.lethal.shape)
            return rows, cols
        _, (rows, cols) = ndimage.distance_transform_edt(self.lethal, return_indices=True)
        return rows, cols

    def lethal_at(self, x, y) -> np.ndarray:
        """True where world points are lethal or outside the map."""
        rows, cols = self.grid.to_cells(x, y)
        ok = self.grid.inside(rows, cols)
        out = np.ones(np.shape(rows), dtype=bool)
        out[ok] = self.lethal[rows[ok], cols[ok]]
        return out

    def with_obstacles(self, points, size=0.15) -> "CostMap":
        """A copy with extra obstacles: every cell within `size` m (one for all, or one per
        point) of a point becomes occupied.

        Re-planning around what blocks the way; the result is not cached."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        sizes = np.broadcast_to(np.asarray(size, dtype=float), (len(points),))
        grid = self.grid
        occupied = grid.occupied.copy()
        for radius in np.unique(sizes):
            chosen = points[sizes == radius]
            reach = int(math.ceil(radius / grid.resolution))
            rows, cols = grid.to_cells(chosen[:, 0], chosen[:, 1])
            for dr in range(-reach, reach + 1):
                for dc in range(-reach, reach + 1):
                    if math.hypot(dr, dc) * grid.resolution > radius + 1e-9:
                        continue
                    r, c = rows + dr, cols + dc
                    ok = grid.inside(r, c)
                    occupied[r[ok], c[ok]] = True
        field = (ndimage.distance_transform_edt(~occupied) * grid.resolution
                 if occupied.any() else np.full(occupied.shape, np.inf))
        lethal, cost = _inflate(field, grid, self.radius, self.band, self.decay,
                                self.unknown_cost, self.inscribed)
        return CostMap(grid, self.radius, self.band, self.decay, self.unknown_cost, lethal, cost,
                       field, self.inscribed)


def cost_map(grid: GridMap, radius: float, *, band: float = INFLATION_BAND, decay: float = DECAY,
             unknown_cost: float | None = None, inscribed: float | None = None) -> CostMap:
    """The cost map of `grid` for a robot of bounding `radius` m (cached per map and parameters).

    `unknown_cost`: None makes unknown cells lethal; a number in [0, 1] lets paths cross them.
    `inscribed`: a footprint that is not round: lethal only within this radius (m)."""
    if not (math.isfinite(radius) and radius > 0):
        raise ValueError(f"robot radius {radius!r} m must be a positive number")
    if unknown_cost is not None and not 0.0 <= unknown_cost <= 1.0:
        raise ValueError(f"unknown_cost {unknown_cost!r} must be None (lethal) or within 0 … 1")
    if inscribed is not None and not 0.0 < inscribed <= radius:
        raise ValueError(f"inscribed radius {inscribed!r} m must be within 0 … {radius} "
                         "(the bounding radius)")
    if inscribed is not None and inscribed == radius:
        inscribed = None
    params = (float(band), float(decay), unknown_cost)
    per_map = _cache.setdefault(grid, {})
    key = (float(radius), params, inscribed)
    if key not in per_map:
        lethal, cost = _inflate(grid.distance_field, grid, radius, *params, inscribed)
        per_map[key] = CostMap(grid, float(radius), *params, lethal, cost, grid.distance_field,
                               inscribed)
    return per_map[key]


def robot_cost_map(grid: GridMap, footprint: Footprint, safety_margin: float) -> CostMap:
    """The cost map a robot plans on: its footprint grown by the local controller's
    `safety_margin` and by what the controller allows for a wall lying anywhere in its cell
    (the diagonal half cell, less the half cell the lethal test already counts). A path then
    never asks the controller for a pose it refuses (a path cut closer to a door's jamb than
    the controller lets the body go made a round robot stop there)."""
    grow = safety_margin + grid.resolution * (math.sqrt(0.5) - 0.5)
    return cost_map(grid, footprint.circumscribed + grow, inscribed=footprint.inscribed + grow)


def _inflate(field: np.ndarray, grid: GridMap, radius: float, band: float, decay: float,
             unknown_cost: float | None,
             inscribed: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    lethal_distance = radius + grid.resolution / 2
    lethal = field < lethal_distance
    beyond = field - lethal_distance
    cost = np.where(beyond <= band, np.exp(-np.maximum(beyond, 0.0) / decay), 0.0)
    cost[lethal] = 1.0
    if inscribed is not None:
        lethal = field < inscribed + grid.resolution / 2
    if grid.unknown is not None:
        if unknown_cost is None:
            lethal = lethal | grid.unknown
        else:
            cost = np.where(grid.unknown, np.maximum(cost, unknown_cost), cost)
    return lethal, cost.astype(float)
