"""Ray casting against wall segments and circles, vectorised over rays and obstacles.

Pure geometry, no I/O: the sonar, the laser, the person detector's occlusion test and the
collision checks all reduce to these few array expressions. It is on the hot path (every tick
casts ~230 rays), so there is no Python loop over rays or obstacles, except in
`nearest_segment`, which runs over the few walls near a body, where numpy's call overhead
would cost more than the loop.
"""
from __future__ import annotations

import math

import numpy as np



def cast_rays(origins: np.ndarray, angles: np.ndarray, segments: np.ndarray,
              circles: np.ndarray, max_range: float,
              segment_hits: np.ndarray | None = None) -> np.ndarray:
    """Distance along each ray to the nearest segment or circle; `np.inf` beyond `max_range`.

    origins: (n, 2) ray starts; angles: (n,) world-frame directions in rad;
    segments: (m, 4) rows x1, y1, x2, y2; circles: (k, 3) rows cx, cy, r.
    A ray starting inside a circle reads 0 (the obstacle touches the sensor). One origin row
    (1, 2) serves every ray (a laser): what depends on the origin alone is computed once.
    `segment_hits`, when given, is what `segment_distances` returned for these rays and
    segments (walls do not move: a sensor that has not moved reuses them).
    """
    px, py, angles = _rays(origins, angles)
    # (obstacle, ray) layout: the final min runs along the long axis, which numpy does fast
    dx = np.cos(angles)
    dy = np.sin(angles)
    best = np.full(angles.shape[0], np.inf)
    if segment_hits is not None:
        best = np.minimum(best, segment_hits)
    elif segments is not None and len(segments):
        best = np.minimum(best, _segment_hits(px, py, dx, dy, segments))
    if circles is not None and len(circles):
        best = np.minimum(best, _circle_hits(px, py, dx, dy, circles))
    best[best > max_range] = np.inf
    return best


def segment_distances(origins: np.ndarray, angles: np.ndarray,
                      segments: np.ndarray) -> np.ndarray:
    """Distance along each ray to the nearest segment, `np.inf` when none (no range limit)."""
    px, py, angles = _rays(origins, angles)
    if segments is None or not len(segments):
        return np.full(angles.shape[0], np.inf)
    return _segment_hits(px, py, np.cos(angles), np.sin(angles), segments)


def _rays(origins, angles) -> tuple:
    """(px, py, angles): the origins' columns, or two floats when one origin serves all rays
    (then the origin's terms are (obstacle, 1) columns instead of (obstacle, ray) tables,
    with the same values)."""
    origins = np.asarray(origins, dtype=float).reshape(-1, 2)
    angles = np.asarray(angles, dtype=float).reshape(-1)
    if origins.shape[0] == 1:
        return float(origins[0, 0]), float(origins[0, 1]), angles
    return origins[:, 0], origins[:, 1], angles


_SMALLEST_NORMAL = np.finfo(float).tiny


def _segment_hits(px, py, dx, dy, segments: np.ndarray) -> np.ndarray:
    """Nearest ray parameter t >= 0 where each ray crosses a segment (inf when none)."""
    ax = segments[:, 0:1]
    ay = segments[:, 1:2]
    ex = segments[:, 2:3] - ax
    ey = segments[:, 3:4] - ay
    qx = ax - px                      # (m, n): ray origin to segment start
    qy = ay - py
    denom = dx * ey - dy * ex         # cross(d, e); 0 when parallel
    t_num = qx * ey - qy * ex         # cross(q, e)
    s_num = qx * dy - qy * dx         # cross(q, d)
    # a ray (nearly) parallel to a segment divides by (nearly) 0: t and s come out infinite
    # (or NaN), and such a pair is no hit below
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        t = t_num / denom
        s = s_num / denom
    # a cross product below the smallest normal float has lost its digits (a wall nearly
    # along the ray, given in subnormal coordinates): its t and s say nothing, no hit
    hit = (np.abs(denom) >= _SMALLEST_NORMAL) & (t >= 0.0) & (s >= 0.0) & (s <= 1.0)
    return np.where(hit, t, np.inf).min(axis=0)


def _circle_hits(px, py, dx, dy, circles: np.ndarray) -> np.ndarray:
    """Nearest ray parameter t >= 0 where each ray enters a circle (0 when it starts inside)."""
    fx = circles[:, 0:1] - px         # (k, n): ray origin to circle centre
    fy = circles[:, 1:2] - py
    b = fx * dx + fy * dy             # projection of the centre on the ray
    c = fx * fx + fy * fy - circles[:, 2:3] ** 2
    disc = b * b - c
    with np.errstate(invalid="ignore"):
        t = b - np.sqrt(disc)
    inside = c <= 0.0                 # (k, 1) or (k, n): the origin inside the circle
    if inside.any():                  # (rarely: most sensors stand clear of everyone)
        t = np.where(inside, 0.0, t)
    hit = (disc >= 0.0) & (t >= 0.0)
    return np.where(hit, t, np.inf).min(axis=0)


def point_segment_distances(x: float, y: float, segments: np.ndarray) -> np.ndarray:
    """Distance from the point (x, y) to each segment, (m,)."""
    if segments is None or not len(segments):
        return np.zeros(0)
    ax = segments[:, 0]
    ay = segments[:, 1]
    ex = segments[:, 2] - ax
    ey = segments[:, 3] - ay
    length2 = ex * ex + ey * ey
    with np.errstate(divide="ignore", invalid="ignore"):
        u = ((x - ax) * ex + (y - ay) * ey) / length2
    u = np.clip(np.nan_to_num(u, nan=0.0), 0.0, 1.0)
    cx = ax + u * ex - x
    cy = ay + u * ey - y
    return np.sqrt(cx * cx + cy * cy)


def nearest_segment(x: float, y: float, segments: np.ndarray) -> float:
    """Distance from (x, y) to the nearest segment (floors have no zero-length walls). Plain
    Python: it runs every substep over the few walls near the body, where numpy's call
    overhead would dominate."""
    best = math.inf
    for x1, y1, x2, y2 in segments.tolist():
        ex, ey = x2 - x1, y2 - y1
        u = min(1.0, max(0.0, ((x - x1) * ex + (y - y1) * ey) / (ex * ex + ey * ey)))
        best = min(best, math.hypot(x1 + u * ex - x, y1 + u * ey - y))
    return best


def nearest_of_many_segments(x: float, y: float, segments: np.ndarray) -> float:
    """`nearest_segment` over many walls, vectorised (inf without any)."""
    if not len(segments):
        return math.inf
    ax, ay = segments[:, 0], segments[:, 1]
    ex, ey = segments[:, 2] - ax, segments[:, 3] - ay
    u = np.clip(((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey), 0.0, 1.0)
    return float(np.hypot(ax + u * ex - x, ay + u * ey - y).min())
