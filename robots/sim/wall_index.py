"""Which walls are near a point, looked up in a grid instead of measured against every wall.

People feel walls only within a short reach (their social force and the rule that keeps bodies
out of walls), yet the nearest wall was searched over every segment of the floor for every
person twice per substep: 20 segments in the office, thousands in a building made from a
map_server map. The index keeps, for each square cell of the floor, the segments that can be
within `reach` of some point of the cell; a query measures only those. The answer is exact for
every point whose nearest wall is within `reach` (the same segment and the same arithmetic as
the full search); a point with no wall within `reach` gets a point far away, as the full search
does on a floor without walls.
"""
from __future__ import annotations

import math

import numpy as np

FAR = 1e6          # m; the answer on a floor without walls
FEW_WALLS = 64     # up to this many segments a search over all is quicker than the lookup
FEW_POSITIONS = 32  # up to this many positions a plain loop looks up bounds quicker than numpy


class WallIndex:
    """Segments (m, 4) as x1, y1, x2, y2 rows, bucketed by square cells of `cell` m."""

    def __init__(self, segments: np.ndarray, reach: float, cell: float = 0.5) -> None:
        self.segments = segments
        self.reach = reach
        self.cell = cell
        self._lower: _LowerBounds | None = None
        self._cell_walls: dict[int, list[tuple[float, float, float, float]]] = {}
        self._full = len(segments) <= FEW_WALLS
        if self._full:
            self._pairs = _segment_pairs(segments)       # the same for every query
        if len(segments):
            self._grid(segments, reach, cell)

    def _grid(self, segments: np.ndarray, reach: float, cell: float) -> None:
        """The cells and their segments (also for few walls: `clear_of` looks there)."""
        low = np.minimum(segments[:, :2], segments[:, 2:]).min(axis=0) - reach
        high = np.maximum(segments[:, :2], segments[:, 2:]).max(axis=0) + reach
        self.origin = low
        self._origin = tuple(low.tolist())            # the same, for plain floats
        self.shape = tuple(int(k) for k in np.ceil((high - low) / cell).astype(int) + 1)
        self._last_cell = np.array(self.shape) - 1
        self._candidates = self._bucket(segments)
        # padded with a segment far away, so that every cell has as many rows
        self._padded = np.vstack([segments, [[FAR, FAR, FAR, FAR]]])

    def _bucket(self, segments: np.ndarray) -> np.ndarray:
        """(cells, k) segment indices per cell, padded with the far segment's index."""
        nx, ny = self.shape
        xs = self.origin[0] + (np.arange(nx) + 0.5) * self.cell
        ys = self.origin[1] + (np.arange(ny) + 0.5) * self.cell
        centres = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
        radius = self.reach + self.cell * math.sqrt(2.0) / 2.0
        near = np.zeros((len(centres), len(segments)), dtype=bool)
        for start in range(0, len(segments), 256):           # bounded memory on big maps
            chunk = segments[start:start + 256]
            near[:, start:start + len(chunk)] = _distances(centres, chunk) <= radius
        width = max(1, int(near.sum(axis=1).max()))
        table = np.full((len(centres), width), len(segments), dtype=np.intp)
        for row in np.flatnonzero(near.any(axis=1)):
            found = np.flatnonzero(near[row])
            table[row, :len(found)] = found
        return table

    def clear_of(self, x: float, y: float, distance: float) -> bool:
        """True when no wall comes within `distance` (at most `reach`) of the point (x, y),
        up to rounding (far below a µm): measured in plain floats over the walls of the
        point's cell, for a few points where numpy's call overhead outweighs the work."""
        if len(self.segments) == 0:
            return True
        ox, oy = self._origin
        i, j = math.floor((x - ox) / self.cell), math.floor((y - oy) / self.cell)
        nx, ny = self.shape
        if not (0 <= i < nx and 0 <= j < ny):
            return True             # off the grid: farther than reach from every wall
        for x1, y1, x2, y2 in self._walls_of_cell(i * ny + j):
            ex, ey = x2 - x1, y2 - y1
            u = min(1.0, max(0.0, ((x - x1) * ex + (y - y1) * ey) / max(ex * ex + ey * ey,
                                                                          1e-18)))
            if math.hypot(x1 + u * ex - x, y1 + u * ey - y) < distance:
                return False
        return True

    def _walls_of_cell(self, cell: int) -> list[tuple[float, float, float, float]]:
        """The segments of one cell as plain floats (kept: a crowd asks about a few cells)."""
        walls = self._cell_walls.get(cell)
        if walls is None:
            rows = self._candidates[cell]
            walls = self._cell_walls[cell] = self.segments[rows[rows < len(self.segments)]
                                                           ].tolist()
        return walls

    def lower_bounds(self, positions: np.ndarray) -> np.ndarray:
        """For each position (n, 2) a lower bound of its distance to the nearest wall (inf
        without walls; 0 off the index's grid), kept per cell of a coarse grid. Lets a caller
        measure only the positions near walls: in a hallway most people are far from both
        walls most of the time."""
        if len(self.segments) == 0:
            return np.full(len(positions), np.inf)
        if self._lower is None:
            self._lower = _LowerBounds(self.segments)
        return self._lower.bounds(positions)

    def nearest_points(self, positions: np.ndarray) -> np.ndarray:
        """For each position (n, 2) the nearest point of any wall (n, 2), exact where that
        wall is within `reach`; a point farther than `reach` otherwise (FAR beyond the
        position on a floor without walls)."""
        if len(self.segments) == 0 or len(positions) == 0:
            return positions + FAR
        if self._full:
            return _nearest_of_all(positions, self._pairs)
        # a point off the grid is farther than reach from every wall: its clamped cell's
        # walls give some point farther still
        cells = ((positions - self.origin) / self.cell).astype(np.intp)
        np.clip(cells, 0, self._last_cell, out=cells)
        candidates = self._candidates[cells[:, 0] * self.shape[1] + cells[:, 1]]    # (n, k)
        return _nearest_of(positions, self._padded[candidates])


class _LowerBounds:
    """A lower bound of the distance to the nearest wall per square cell: the distance from
    the cell's centre less half its diagonal. Off the grid nothing is known (0)."""

    CELL = 0.25          # m
    MARGIN = 1.0         # m of grid around the walls

    def __init__(self, segments: np.ndarray) -> None:
        low = np.minimum(segments[:, :2], segments[:, 2:]).min(axis=0) - self.MARGIN
        high = np.maximum(segments[:, :2], segments[:, 2:]).max(axis=0) + self.MARGIN
        self.origin = low
        nx, ny = (int(k) for k in np.ceil((high - low) / self.CELL).astype(int))
        self.shape = (nx, ny)
        xs = low[0] + (np.arange(nx) + 0.5) * self.CELL
        ys = low[1] + (np.arange(ny) + 0.5) * self.CELL
        centres = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
        nearest = np.full(len(centres), np.inf)
        for start in range(0, len(segments), 256):            # bounded memory on big maps
            chunk = _distances(centres, segments[start:start + 256])
            nearest = np.minimum(nearest, chunk.min(axis=1))
        slack = 1e-9      # m: the rounding of the distances is far below it
        self.bound = (nearest - self.CELL * math.sqrt(2.0) / 2.0 - slack).reshape(nx, ny)
        self._rows = self.bound.tolist()       # the same bounds, for the plain loop
        self._origin = tuple(self.origin.tolist())

    def bounds(self, positions: np.ndarray) -> np.ndarray:
        """The bound of each position's cell (n,)."""
        if len(positions) <= FEW_POSITIONS:
            return self._bounds_few(positions)
        cells = np.floor((positions - self.origin) / self.CELL).astype(np.intp)
        inside = ((cells[:, 0] >= 0) & (cells[:, 0] < self.shape[0])
                  & (cells[:, 1] >= 0) & (cells[:, 1] < self.shape[1]))
        bound = np.zeros(len(positions))
        bound[inside] = self.bound[cells[inside, 0], cells[inside, 1]]
        return bound

    def _bounds_few(self, positions: np.ndarray) -> np.ndarray:
        """`bounds` for a few positions in plain Python (the same arithmetic: numpy's call
        overhead outweighs the work for a crowd of ten, queried twice per substep)."""
        ox, oy = self._origin
        nx, ny = self.shape
        rows, cell = self._rows, self.CELL
        out = []
        for x, y in positions.tolist():
            i, j = math.floor((x - ox) / cell), math.floor((y - oy) / cell)
            out.append(rows[i][j] if 0 <= i < nx and 0 <= j < ny else 0.0)
        return np.array(out)


def _segment_parts(segments: np.ndarray) -> tuple[np.ndarray, ...]:
    """x1, y1, ex, ey and squared length of segments (…, 4): what `_nearest_of` needs."""
    x1, y1, x2, y2 = (segments[..., k] for k in range(4))
    ex, ey = x2 - x1, y2 - y1
    return x1, y1, ex, ey, np.maximum(ex * ex + ey * ey, 1e-18)


def _segment_pairs(segments: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Starts (1, 2, m), directions (1, 2, m) and squared lengths (1, m) of segments (m, 4),
    x above y: what `_nearest_of_all` needs."""
    x1, y1, ex, ey, length = _segment_parts(segments)
    return (np.stack([x1, y1])[None], np.stack([ex, ey])[None], length[None])


def _nearest_of_all(positions: np.ndarray, pairs: tuple[np.ndarray, ...]) -> np.ndarray:
    """`_nearest_of` over the same segments for every position, with x and y side by side
    in one array: the same arithmetic in half the numpy calls (a sum over an axis of two is
    the one addition `a + b`)."""
    start, direction, length = pairs
    at = positions[:, :, None]                                              # (n, 2, 1)
    along = np.add.reduce((at - start) * direction, axis=1) / length        # (n, m)
    u = np.minimum(np.maximum(along, 0.0), 1.0)
    points = start + u[:, None, :] * direction                              # (n, 2, m)
    nearest = np.argmin(np.add.reduce((points - at) ** 2, axis=1), axis=1)
    return points[np.arange(len(positions)), :, nearest]


def _nearest_of(positions: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Nearest point per position (n, 2) among its own segments (n, k, 4); the first of
    equally near ones, as a search in index order gives."""
    x, y = positions[:, 0:1], positions[:, 1:2]
    x1, y1, ex, ey, length = _segment_parts(segments)
    # np.clip's wrapper costs more than its work here; maximum then minimum is the same
    u = np.minimum(np.maximum(((x - x1) * ex + (y - y1) * ey) / length, 0.0), 1.0)
    px, py = x1 + u * ex, y1 + u * ey
    nearest = np.argmin((px - x) ** 2 + (py - y) ** 2, axis=1)
    rows = np.arange(len(positions))
    out = np.empty((len(positions), 2))
    out[:, 0] = px[rows, nearest]
    out[:, 1] = py[rows, nearest]
    return out


def _distances(points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distance of each point (p, 2) to each segment (m, 4): (p, m)."""
    x, y = points[:, 0:1], points[:, 1:2]
    x1, y1, x2, y2 = (segments[:, k][None, :] for k in range(4))
    ex, ey = x2 - x1, y2 - y1
    length = np.maximum(ex * ex + ey * ey, 1e-18)
    u = np.clip(((x - x1) * ex + (y - y1) * ey) / length, 0.0, 1.0)
    return np.hypot(x1 + u * ex - x, y1 + u * ey - y)


__all__ = ["WallIndex", "FAR"]
