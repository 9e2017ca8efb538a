"""How far the robot turned and moved between two laser scans taken standing still: the start-up
self-check's witness that does not come from the drives (issue 24 point 1).

The encoders can agree with their own commands and still be wrong about the robot: a motor
mounted the other way round than the profile says, wheels swapped, a wrong track width or
wheel radius. The laser sees the robot's real turn. Pure: two scans in, a turn out.

Method: the ranges of the second scan, read at each beam's angle shifted by a candidate turn
(linear interpolation between beams), are compared with the first scan's; the turn whose median
absolute difference is smallest wins (a coarse grid, then a fine one around the best). A small
translation (a few cm) and a few moving legs barely change the median. The advance: the second
scan's points, turned back, are shifted forward or back until they lie nearest the first's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

SEARCH = math.radians(12.0)      # the largest turn looked for, either way
COARSE = math.radians(0.25)
FINE = math.radians(0.02)
MIN_BEAMS = 30                   # beams with an echo in both scans needed for a verdict
MAX_RESIDUAL = 0.05              # m: a best median difference above this is no match


@dataclass(frozen=True)
class Turn:
    radians: float        # counter-clockwise seen from above, as the robot's heading
    residual: float       # m: the median range difference at that turn
    beams: int            # beams compared

    @property
    def trusted(self) -> bool:
        return self.beams >= MIN_BEAMS and self.residual <= MAX_RESIDUAL


def turn_between(angles: np.ndarray, before: np.ndarray, after: np.ndarray) -> Turn:
    """The robot's turn from the scan `before` to the scan `after` (same beam `angles`, robot
    frame, ascending; ranges in m, inf for no echo). The robot turning by d moves a fixed
    point from beam angle a to a - d, so `after(a - d)` matches `before(a)`."""
    angles = np.asarray(angles, dtype=float)
    before = np.asarray(before, dtype=float)
    after = np.asarray(after, dtype=float)
    best = _search(angles, before, after, np.arange(-SEARCH, SEARCH + COARSE / 2, COARSE))
    fine = np.arange(best.radians - COARSE, best.radians + COARSE + FINE / 2, FINE)
    return _search(angles, before, after, fine)


def _search(angles, before, after, candidates) -> Turn:
    best = Turn(0.0, math.inf, 0)
    finite_after = np.isfinite(after)
    after = np.where(finite_after, after, 0.0)
    for turn in candidates:
        shifted = angles - turn
        inside = (shifted >= angles[0]) & (shifted <= angles[-1]) & np.isfinite(before)
        if not inside.any():
            continue
        index = np.clip(np.searchsorted(angles, shifted[inside]) - 1, 0, len(angles) - 2)
        left, right = index, index + 1
        usable = finite_after[left] & finite_after[right]
        if usable.sum() < MIN_BEAMS:
            continue
        weight = (shifted[inside] - angles[left]) / (angles[right] - angles[left])
        read = after[left] * (1 - weight) + after[right] * weight
        diff = np.abs(read[usable] - before[inside][usable])
        residual = float(np.median(diff))
        if residual < best.residual:
            best = Turn(float(turn), residual, int(usable.sum()))
    return best


ADVANCE_SEARCH = 0.06            # m: the largest advance looked for, either way
ADVANCE_STEP = 0.002
NEAR = 6.0                       # m: farther echoes are too sparse to place a point


@dataclass(frozen=True)
class Advance:
    metres: float         # forward in the robot frame
    residual: float       # m: the median distance of the second scan's points to the first's
    points: int

    @property
    def trusted(self) -> bool:
        return self.points >= MIN_BEAMS and self.residual <= MAX_RESIDUAL


def advance_between(angles: np.ndarray, before: np.ndarray, after: np.ndarray,
                    turn: float) -> Advance:
    """How far the robot moved forward between the scans, given its `turn` between them: the
    second scan's points, turned back and shifted by a candidate advance, lie nearest the
    first scan's points (median nearest-point distance) at the robot's real advance."""
    angles = np.asarray(angles, dtype=float)
    first = _points(angles, np.asarray(before, dtype=float))
    second = _points(angles, np.asarray(after, dtype=float))
    if len(first) < MIN_BEAMS or len(second) < MIN_BEAMS:
        return Advance(0.0, math.inf, min(len(first), len(second)))
    c, s = math.cos(turn), math.sin(turn)
    turned = second @ np.array([[c, s], [-s, c]])
    coarse = _best_advance(first, turned, np.arange(-ADVANCE_SEARCH, ADVANCE_SEARCH + 1e-9, 0.005))
    return _best_advance(first, turned, np.arange(coarse.metres - 0.005, coarse.metres + 0.005 + 1e-9,
                                                  ADVANCE_STEP))


def _best_advance(first: np.ndarray, turned: np.ndarray, candidates) -> Advance:
    best = Advance(0.0, math.inf, len(turned))
    for dx in candidates:
        moved = turned + np.array([dx, 0.0])
        gaps = np.sqrt(((moved[:, None, :] - first[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
        residual = float(np.median(gaps))
        if residual < best.residual:
            best = Advance(float(dx), residual, len(turned))
    return best


def _points(angles: np.ndarray, ranges: np.ndarray) -> np.ndarray:
    near = np.isfinite(ranges) & (ranges < NEAR)
    return np.column_stack((ranges[near] * np.cos(angles[near]), ranges[near] * np.sin(angles[near])))
