"""The robot body's outline in the simulated world: an oriented rectangle for a box-shaped base
(HOROS's 0.445 m × 0.393 m), so contacts and gaps are those of the real footprint, not of a
bounding circle that cuts its corners (0.26 m against 0.297 m) and pads its sides (0.26 m
against 0.197 m).

Gaps are between outlines: negative means overlap. A round body needs none of this (its gap is
the centre's distance less its radius), so `UnicycleBody` keeps that path for round robots.
"""
from __future__ import annotations

import math

import numpy as np

INSIDE_SAMPLES = 9          # points along the part of a wall inside the rectangle
CORNER_RADIUS = 0.10        # m: the circles filling a rectangle's corners
CORNER_SLACK = (math.sqrt(2) - 1) * CORNER_RADIUS   # m a corner sticks out of them (0.041)


class Rectangle:
    """A rectangle `length` along the heading by `width` across, centred on the pose."""

    def __init__(self, length: float, width: float) -> None:
        self.half_length = float(length) / 2
        self.half_width = float(width) / 2
        self.half_diagonal = math.hypot(self.half_length, self.half_width)   # centre to corner
        self.corners = np.array([[self.half_length, self.half_width],
                                 [self.half_length, -self.half_width],
                                 [-self.half_length, -self.half_width],
                                 [-self.half_length, self.half_width]])
        self._last_wall_gap: tuple | None = None     # (x, y, th, segments, gap)

    def circles(self, x: float, y: float, th: float) -> np.ndarray:
        """(6, 3) circles cx, cy, r that fill the rectangle at pose (x, y, th), for what
        handles bodies as circles (people keeping out of the robot): two of the half width
        along it, reaching its front and back, and one inside each corner (each corner sticks
        out of them by CORNER_SLACK)."""
        hl, hw = self.half_length, self.half_width
        small = min(CORNER_RADIUS, hw)
        local = [(hl - hw, 0.0, hw), (hw - hl, 0.0, hw)] + [
            (sx * (hl - small), sy * (hw - small), small) for sx in (1, -1) for sy in (1, -1)]
        c, s = math.cos(th), math.sin(th)
        return np.array([(x + c * bx - s * by, y + s * bx + c * by, r) for bx, by, r in local])

    def signed_distances(self, bx: np.ndarray, by: np.ndarray) -> np.ndarray:
        """Signed distance of body-frame points to the outline (negative inside)."""
        qx = np.abs(bx) - self.half_length
        qy = np.abs(by) - self.half_width
        outside = np.hypot(np.maximum(qx, 0.0), np.maximum(qy, 0.0))
        return outside + np.minimum(np.maximum(qx, qy), 0.0)

    def gap_to_point(self, x: float, y: float, th: float, px: float, py: float) -> float:
        """Gap from the rectangle at pose (x, y, th) to the point (px, py)."""
        c, s = math.cos(th), math.sin(th)
        dx, dy = px - x, py - y
        bx, by = c * dx + s * dy, -s * dx + c * dy
        qx, qy = abs(bx) - self.half_length, abs(by) - self.half_width
        return math.hypot(max(qx, 0.0), max(qy, 0.0)) + min(max(qx, qy), 0.0)

    def gap_to_circles(self, x: float, y: float, th: float, circles: np.ndarray) -> np.ndarray:
        """(k,) gaps from the rectangle at pose (x, y, th) to circles (k, 3) cx, cy, r."""
        bx, by = _to_body(x, y, th, circles[:, 0], circles[:, 1])
        return self.signed_distances(bx, by) - circles[:, 2]

    def gap_to_segments(self, x: float, y: float, th: float, segments: np.ndarray) -> float:
        """The smallest gap from the rectangle at pose (x, y, th) to wall segments (m, 4).

        Apart, the nearest points are an end of a wall or a corner of the rectangle; a wall
        crossing the rectangle gives the deepest of points sampled along its inside part.
        The last answer is kept: the world asks twice per substep (the collision stop and the
        measures) and again and again while the robot stands, at the same pose."""
        last = self._last_wall_gap
        if last is not None and last[3] is segments and last[:3] == (x, y, th):
            return last[4]
        gap = self._gap_to_segments(x, y, th, segments)
        self._last_wall_gap = (x, y, th, segments, gap)
        return gap

    def known_gap(self, x: float, y: float, th: float, segments: np.ndarray) -> float | None:
        """The gap `gap_to_segments` last found, if it was for this pose and these segments
        (the same object), else None."""
        last = self._last_wall_gap
        if last is not None and last[3] is segments and last[:3] == (x, y, th):
            return last[4]
        return None

    def _gap_to_segments(self, x: float, y: float, th: float, segments: np.ndarray) -> float:
        if not len(segments):
            return math.inf
        ax, ay = _to_body(x, y, th, segments[:, 0], segments[:, 1])
        bx, by = _to_body(x, y, th, segments[:, 2], segments[:, 3])
        ends = np.minimum(self.signed_distances(ax, ay), self.signed_distances(bx, by))
        ex, ey = bx - ax, by - ay
        length2 = np.maximum(ex * ex + ey * ey, 1e-12)
        cx, cy = self.corners[:, 0, None], self.corners[:, 1, None]          # 4 × m
        u = np.clip(((cx - ax) * ex + (cy - ay) * ey) / length2, 0.0, 1.0)
        corners = np.hypot(ax + u * ex - cx, ay + u * ey - cy).min(axis=0)
        gaps = np.minimum(ends, corners)
        t0, t1 = self._inside_part(ax, ay, ex, ey)
        crossing = t0 <= t1
        if crossing.any():
            t = t0[crossing, None] + (t1 - t0)[crossing, None] * np.linspace(0, 1, INSIDE_SAMPLES)
            px = ax[crossing, None] + t * ex[crossing, None]
            py = ay[crossing, None] + t * ey[crossing, None]
            gaps[crossing] = np.minimum(gaps[crossing],
                                        self.signed_distances(px, py).min(axis=1))
        return float(gaps.min())

    def _inside_part(self, ax, ay, ex, ey) -> tuple[np.ndarray, np.ndarray]:
        """The parameters [t0, t1] of each segment a + t e (t in 0..1) inside the rectangle
        (t0 > t1: none), by clipping against its two slabs."""
        t0, t1 = np.zeros(len(ax)), np.ones(len(ax))
        for start, step, half in ((ax, ex, self.half_length), (ay, ey, self.half_width)):
            flat = np.abs(step) < 1e-12
            with np.errstate(divide="ignore", invalid="ignore"):
                lo = np.where(flat, -np.inf, (-half - start) / step)
                hi = np.where(flat, np.inf, (half - start) / step)
            t0 = np.maximum(t0, np.minimum(lo, hi))
            t1 = np.minimum(t1, np.maximum(lo, hi))
            t1 = np.where(flat & (np.abs(start) > half), -np.inf, t1)   # parallel, outside
        return t0, t1


def _to_body(x: float, y: float, th: float, px, py) -> tuple[np.ndarray, np.ndarray]:
    c, s = math.cos(th), math.sin(th)
    dx, dy = np.asarray(px, float) - x, np.asarray(py, float) - y
    return c * dx + s * dy, -s * dx + c * dy
