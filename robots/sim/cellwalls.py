"""Walls from cells: the outline of a map's solid cells as few, long line segments.

The simulator's sensors and collisions work on wall segments (`robots.sim.raycast`), whose
cost grows with their number. A map has hundreds of thousands of cells, but only the edges
between a solid cell and a free one can stop a ray or a body, and along a straight wall those
edges line up. So the walls are the cell edges on the boundary of the solid region, merged
into maximal runs along each grid line: a 10 m wall of any thickness is two segments (its two
faces), a cabinet four, the inside of a thick filled wall none. `benchmarks/bench_cellwalls.py`
measures what that costs the ray casting against the bundled office.

Outside the grid counts as solid, so free cells on the map's edge are closed off too.
"""
from __future__ import annotations

import numpy as np


def outline_segments(solid: np.ndarray, resolution: float,
                     origin: tuple[float, float]) -> np.ndarray:
    """(m, 4) segments x1, y1, x2, y2 along every edge between a solid and a free cell.

    `solid` is rows × cols with row 0 at the bottom (y = origin_y); cell (r, c) covers
    x in [origin_x + c·res, +res), y in [origin_y + r·res, +res)."""
    solid = np.asarray(solid, dtype=bool)
    padded = np.pad(solid, 1, constant_values=True)
    # horizontal edges: between rows r-1 and r of the map (r = 0 .. rows), for each column
    across_rows = padded[1:, 1:-1] != padded[:-1, 1:-1]          # (rows + 1, cols)
    # vertical edges: between columns c-1 and c (c = 0 .. cols), for each row
    across_cols = padded[1:-1, 1:] != padded[1:-1, :-1]          # (rows, cols + 1)
    x0, y0 = origin
    lines_h, starts_h, ends_h = _runs(across_rows)
    horizontal = np.column_stack([x0 + starts_h * resolution, y0 + lines_h * resolution,
                                  x0 + ends_h * resolution, y0 + lines_h * resolution])
    lines_v, starts_v, ends_v = _runs(across_cols.T)
    vertical = np.column_stack([x0 + lines_v * resolution, y0 + starts_v * resolution,
                                x0 + lines_v * resolution, y0 + ends_v * resolution])
    return np.vstack([horizontal, vertical]).astype(float)


def _runs(edges: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Maximal runs of True along each row of `edges`: (row, first, one past last) arrays."""
    flags = np.pad(edges.astype(np.int8), ((0, 0), (1, 1)))
    change = np.diff(flags, axis=1)
    # np.nonzero walks row by row, left to right, so the n-th start and the n-th end belong
    # to the same run
    start_rows, starts = np.nonzero(change == 1)
    _, ends = np.nonzero(change == -1)
    return start_rows, starts, ends


__all__ = ["outline_segments"]
