"""The robot's real footprint, as planning and control see it: a circle for a round base, a
rectangle (centred on the axis it turns about) for a box-shaped one.

A round robot is described by its radius. A rectangle has two radii that matter: the
*inscribed* one (half its width: the least room it needs to drive straight through an
opening) and the *circumscribed* one (its corners: the room it needs to turn on the spot).
Planning keeps the centre an inscribed radius (plus a margin) from walls and merely avoids the
band up to the circumscribed radius; control checks the rectangle itself at every simulated
pose, so a box-shaped robot passes an opening a little wider than itself, turned along it.

Distances here are gaps between outlines: negative means overlap.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

BOUNDARY_SPACING = 0.05     # m between the points sampled along a rectangle's outline


@dataclass(frozen=True)
class Footprint:
    """`shape` "round" (radius) or "rectangle" (length along the heading, width across)."""
    shape: str
    radius: float
    length: float = 0.0
    width: float = 0.0

    @classmethod
    def of(cls, profile) -> "Footprint":
        """The footprint a robot profile declares (its [geometry] table)."""
        if profile.shape == "rectangle":
            return cls("rectangle", float(profile.radius), float(profile.length),
                       float(profile.width))
        return cls("round", float(profile.radius))

    @classmethod
    def round(cls, radius: float) -> "Footprint":
        return cls("round", float(radius))

    @property
    def is_round(self) -> bool:
        return self.shape != "rectangle"

    @property
    def inscribed(self) -> float:
        """m: the largest circle about the centre inside the footprint."""
        if self.is_round:
            return self.radius
        return min(self.length, self.width) / 2

    @property
    def circumscribed(self) -> float:
        """m: the smallest circle about the centre around the footprint (at least the profile's
        bounding radius)."""
        if self.is_round:
            return self.radius
        return max(self.radius, math.hypot(self.length / 2, self.width / 2))

    @cached_property
    def outline(self) -> np.ndarray:
        """(n, 2) points along the rectangle's outline in the body frame (corners included)."""
        hl, hw = self.length / 2, self.width / 2
        nx = max(2, int(math.ceil(self.length / BOUNDARY_SPACING)) + 1)
        ny = max(2, int(math.ceil(self.width / BOUNDARY_SPACING)) + 1)
        xs, ys = np.linspace(-hl, hl, nx), np.linspace(-hw, hw, ny)
        sides = [np.column_stack([xs, np.full(nx, hw)]), np.column_stack([xs, np.full(nx, -hw)]),
                 np.column_stack([np.full(ny - 2, hl), ys[1:-1]]),
                 np.column_stack([np.full(ny - 2, -hl), ys[1:-1]])]
        return np.vstack(sides)

    def outline_at(self, x, y, th) -> tuple[np.ndarray, np.ndarray]:
        """The outline's points (..., n) in the map frame at poses of any shape."""
        x, y, th = (np.asarray(v, float)[..., None] for v in (x, y, th))
        c, s = np.cos(th), np.sin(th)
        bx, by = self.outline[:, 0], self.outline[:, 1]
        return x + c * bx - s * by, y + s * bx + c * by

    def gap_to_points(self, x, y, th, points: np.ndarray) -> np.ndarray:
        """(...) gap from the footprint at each pose to the nearest of `points` (k, 2), each
        pose against every point: for a handful of points, or after a k-d tree's preselection
        (`points` then (..., k, 2), one set per pose)."""
        points = np.asarray(points, float)
        x, y, th = (np.asarray(v, float) for v in (x, y, th))
        if points.ndim == 2:
            dx = points[:, 0] - x[..., None]
            dy = points[:, 1] - y[..., None]
        else:
            dx = points[..., 0] - x[..., None]
            dy = points[..., 1] - y[..., None]
        if self.is_round:
            return (np.hypot(dx, dy) - self.radius).min(axis=-1)
        c, s = np.cos(th)[..., None], np.sin(th)[..., None]
        along, across = c * dx + s * dy, -s * dx + c * dy
        return box_gap(along, across, self.length / 2, self.width / 2).min(axis=-1)


TURN_STEP = math.radians(2)     # the turning sweep is checked at poses this far apart
SHRINKING = 0.005               # m: a gap closes by more than this (laser noise is less)


def corner_reach(footprint: Footprint, radius: float, margin: float) -> float:
    """m from the centre within which a disc of `radius` may come within `margin` of the body
    as it turns: farther off, `turn_room` never counts it."""
    return footprint.circumscribed + margin + radius


def turn_room(footprint: Footprint, points: np.ndarray, radius: float = 0.0,
              margin: float = 0.0) -> tuple[float, float]:
    """(left, right): how far (rad) the body can turn on the spot, counter-clockwise and
    clockwise, before its outline comes within `margin` of a disc (centres `points` (k, 2) in
    the body frame, each of `radius`) it now clears by more: a box's corners sweep out to its
    circumscribed radius, so a turn alone may strike someone standing beside it (HOROS backing
    off from a shopper while turning to face them, issue 23). A disc already nearer than that
    stops only the turn that brings it nearer still. Infinite for a round base (its turn sweeps
    nothing) and when no disc is within reach of the corners in half a turn."""
    if footprint.is_round:
        return math.inf, math.inf
    points = np.asarray(points, float).reshape(-1, 2)
    xs, ys = points[:, 0], points[:, 1]
    reach = corner_reach(footprint, radius, margin)
    # most ticks nothing is this near: a squared distance per point, then done
    near = xs * xs + ys * ys < reach * reach
    if not near.any():
        return math.inf, math.inf
    xs, ys = xs[near], ys[near]
    return (_room_turning_left(footprint, xs, ys, radius, margin),
            _room_turning_left(footprint, xs, -ys, radius, margin))


def _room_turning_left(footprint: Footprint, xs, ys, radius: float, margin: float) -> float:
    """`turn_room`'s counter-clockwise answer (the clockwise one is its mirror image)."""
    half_length, half_width = footprint.length / 2, footprint.width / 2
    now = box_gap(xs, ys, half_length, half_width) - radius
    turns = TURN_STEP * np.arange(1, int(round(math.pi / TURN_STEP)) + 1)[:, None]
    c, s = np.cos(turns), np.sin(turns)
    # the body turning by +t is each disc turning by -t about the body's centre
    gaps = box_gap(c * xs + s * ys, c * ys - s * xs, half_length, half_width) - radius
    struck = ((gaps < margin) & (gaps < now - SHRINKING)).any(axis=1)
    first = int(np.argmax(struck))
    return float(first * TURN_STEP) if struck[first] else math.inf


def inside(footprint: Footprint, points: np.ndarray) -> np.ndarray:
    """(k,) True for points (k, 2) in the robot frame that lie within the footprint: a range
    reading there is the robot itself or a stray return, never an obstacle."""
    points = np.asarray(points, float).reshape(-1, 2)
    if footprint.is_round:
        return np.hypot(points[:, 0], points[:, 1]) < footprint.radius
    return box_gap(points[:, 0], points[:, 1], footprint.length / 2, footprint.width / 2) < 0.0


def box_gap(along: np.ndarray, across: np.ndarray, half_length: float,
            half_width: float) -> np.ndarray:
    """Signed distance from points (body frame) to a centred box: outside positive, inside
    negative (the depth to its nearest side)."""
    ox = np.abs(along) - half_length
    oy = np.abs(across) - half_width
    outside = np.hypot(np.maximum(ox, 0.0), np.maximum(oy, 0.0))
    inside = np.minimum(np.maximum(ox, oy), 0.0)
    return outside + inside
