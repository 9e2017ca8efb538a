"""What sonar can honestly say about people: "something new is there, at about this range and
in that cone". Used on robots without a laser or a person detector.

A sonar echo gives the range of the nearest surface in a 20-30 degree cone, nothing about its
shape, and often nothing at all from surfaces hit at a slant. So a candidate is only an echo
clearly nearer than the background (what that sonar reads with nobody there: the map or an
empty-room recording), placed on the cone's axis, with a covariance as wide as the cone.
Neighbouring sonars that see the same thing are merged. Robot frame, source "sonar".
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from robots.devices import Detection


@dataclass(frozen=True)
class SonarParams:
    min_change: float = 0.3     # m an echo must be nearer than the background
    max_range: float = 3.0      # m; farther, a cone is too wide to place anyone
    body_depth: float = 0.2     # m from the reflecting surface to the person's centre
    same_object: float = 0.3    # m; neighbouring echoes closer in range than this merge
    range_sigma: float = 0.1    # m along the beam (surface vs. centre, clothing)


def sonar_candidates(t: float, ranges: np.ndarray, poses: np.ndarray, cone: float,
                     background: np.ndarray | None = None,
                     params: SonarParams | None = None) -> list[Detection]:
    """Person candidates from one sonar sweep: `ranges` (n,) in m from each transducer,
    `poses` (n, 3) x, y, heading in the robot frame, `cone` the full opening angle (rad)."""
    p = params or SonarParams()
    ranges = np.asarray(ranges, dtype=float)
    near = np.isfinite(ranges) & (ranges <= p.max_range)
    if background is not None:
        near &= ranges < np.asarray(background, dtype=float) - p.min_change
    return [_candidate(t, ranges, poses, cone, group, p) for group in _groups(ranges, near, p)]


def _groups(ranges: np.ndarray, near: np.ndarray, p: SonarParams) -> list[list[int]]:
    """Runs of neighbouring triggered sonars (in ring order) with similar ranges."""
    groups: list[list[int]] = []
    for i in np.flatnonzero(near):
        if groups and groups[-1][-1] == i - 1 and abs(ranges[i] - ranges[i - 1]) < p.same_object:
            groups[-1].append(int(i))
        else:
            groups.append([int(i)])
    return groups


def _candidate(t: float, ranges: np.ndarray, poses: np.ndarray, cone: float,
               group: list[int], p: SonarParams) -> Detection:
    """On the mean axis of the group, at the nearest echo plus the body depth; across the
    beam the position is uniform over the cone's width (sigma = width / sqrt(12))."""
    r = float(min(ranges[group])) + p.body_depth
    x0, y0 = poses[group, 0].mean(), poses[group, 1].mean()
    heading = math.atan2(np.sin(poses[group, 2]).mean(), np.cos(poses[group, 2]).mean())
    spread = cone + abs(poses[group[-1], 2] - poses[group[0], 2])
    across = 2.0 * r * math.tan(min(spread, 2.5) / 2.0) / math.sqrt(12.0)
    c, s = math.cos(heading), math.sin(heading)
    rot = np.array([[c, -s], [s, c]])
    cov = rot @ np.diag([p.range_sigma ** 2, across ** 2]) @ rot.T
    return Detection(t=t, x=float(x0 + c * r), y=float(y0 + s * r),
                     cov=tuple(map(tuple, cov.tolist())), source="sonar")
