"""How far the robot turned and moved between two laser scans taken standing still: the start-up
self-check's witness that does not come from the drives (issue 24 point 1).

The encoders can agree with their own commands and still be wrong about the robot: a motor
mounted the other way round than the profile says, wheels swapped, a wrong track width or
wheel radius. The laser sees the robot's real motion. Pure: two scans in, a motion out.

Method (projective scan matching): the second scan's echoes, moved by a candidate motion
(turn, forward, sideways) into the first scan's frame, should lie at the first scan's range in
their direction (the first scan interpolated between beams). A coarse search over turns finds
the basin; Gauss-Newton steps on the three unknowns then minimise the squared range
differences, leaving out the worst (legs that moved, edges seen past): beyond three times the
median difference, at least 3 cm. Small motions only (a few degrees, a few cm).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

SEARCH = math.radians(12.0)      # the largest turn looked for, either way
COARSE = math.radians(0.5)
STEPS = 12                       # Gauss-Newton steps
MIN_BEAMS = 30                   # beams matched in both scans needed for a verdict
MAX_RESIDUAL = 0.05              # m: a median range difference above this is no match
NEAR = 8.0                       # m: farther echoes are left out (sparse, noisy)
JUMP = 0.15                      # m between neighbouring beams: an edge, not interpolated across


@dataclass(frozen=True)
class ScanMotion:
    turn: float           # rad, counter-clockwise seen from above, as the robot's heading
    forward: float        # m, along the laser's heading at the first scan
    sideways: float       # m, to its left
    residual: float       # m: the median range difference at that motion
    beams: int            # echoes matched

    @property
    def trusted(self) -> bool:
        return self.beams >= MIN_BEAMS and self.residual <= MAX_RESIDUAL


def motion_between(angles: np.ndarray, before: np.ndarray, after: np.ndarray) -> ScanMotion:
    """The laser's motion from the scan `before` to the scan `after` (same beam `angles`, the
    laser's frame, ascending; ranges in m, inf for no echo)."""
    angles = np.asarray(angles, dtype=float)
    before = np.asarray(before, dtype=float)
    after = np.asarray(after, dtype=float)
    keep = np.isfinite(after) & (after < NEAR)
    points = np.column_stack((after[keep] * np.cos(angles[keep]), after[keep] * np.sin(angles[keep])))
    if len(points) < MIN_BEAMS:
        return ScanMotion(0.0, 0.0, 0.0, math.inf, len(points))
    finite = np.isfinite(before)
    filled = np.where(finite, before, 0.0)
    coarse = min(((_median_gap(angles, filled, finite, points, (turn, 0.0, 0.0)), turn)
                  for turn in np.arange(-SEARCH, SEARCH + COARSE / 2, COARSE)), key=lambda c: c[0])
    motion = np.array([coarse[1], 0.0, 0.0])
    for _ in range(STEPS):
        step = _gauss_newton_step(angles, filled, finite, points, motion)
        if step is None:
            break
        motion = motion + step
        if np.all(np.abs(step) < (1e-5, 1e-5, 1e-5)):
            break
    gaps, valid = _gaps(angles, filled, finite, points, motion)
    residual = float(np.median(np.abs(gaps[valid]))) if valid.sum() else math.inf
    return ScanMotion(float(motion[0]), float(motion[1]), float(motion[2]), residual, int(valid.sum()))


def _gaps(angles, filled, finite, points, motion) -> tuple[np.ndarray, np.ndarray]:
    """Each moved echo's range minus the first scan's range in its direction, and which of
    them fall between two echoes of the first scan on one surface (no edge between them)."""
    turn, dx, dy = motion
    c, s = math.cos(turn), math.sin(turn)
    x = c * points[:, 0] - s * points[:, 1] + dx
    y = s * points[:, 0] + c * points[:, 1] + dy
    direction = np.arctan2(y, x)
    expected = np.interp(direction, angles, filled)
    between = np.clip(np.searchsorted(angles, direction) - 1, 0, len(angles) - 2)
    smooth = finite[:-1] & finite[1:] & (np.abs(np.diff(filled)) < JUMP)
    valid = smooth[between] & (direction >= angles[0]) & (direction <= angles[-1])
    return np.hypot(x, y) - expected, valid


def _median_gap(angles, filled, finite, points, motion) -> float:
    gaps, valid = _gaps(angles, filled, finite, points, motion)
    return float(np.median(np.abs(gaps[valid]))) if valid.sum() >= MIN_BEAMS else math.inf


def _gauss_newton_step(angles, filled, finite, points, motion) -> np.ndarray | None:
    gaps, valid = _gaps(angles, filled, finite, points, motion)
    if valid.sum() < MIN_BEAMS:
        return None
    bound = max(3.0 * float(np.median(np.abs(gaps[valid]))), 0.03)
    used = valid & (np.abs(gaps) <= bound)
    columns = []
    for k, h in enumerate((1e-4, 1e-4, 1e-4)):          # numerical derivatives
        moved = motion.copy()
        moved[k] += h
        shifted, shifted_valid = _gaps(angles, filled, finite, points, moved)
        used &= shifted_valid
        columns.append((shifted - gaps) / h)
    if used.sum() < MIN_BEAMS:
        return None
    jacobian = np.column_stack(columns)[used]
    step, *_ = np.linalg.lstsq(jacobian, -gaps[used], rcond=None)
    return np.clip(step, (-0.02, -0.02, -0.02), (0.02, 0.02, 0.02))
