"""People in a laser scan: legs are short, isolated arcs; two of them close together are a person.

The scan is cut where the range jumps (or a beam hits nothing); a cut piece as wide as a leg is a
leg candidate, its centre pushed back by a leg radius along the ray because the laser sees the
front of the leg. Legs closer than a stride are paired into one person at their midpoint; a piece
as wide as two legs is a person whose legs overlap in the view; a leg without a partner (the
other hidden behind it) still counts, less certainly.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from robots.devices import Detection, LaserScan


@dataclass(frozen=True)
class LegParams:
    jump: float = 0.12          # m; a range step larger than this starts a new segment
    contrast: float = 0.3       # m; a leg is this much nearer than a neighbour (see _stands_out)
    min_width: float = 0.05     # m; leg-sized segments
    max_width: float = 0.25
    max_both_width: float = 0.5  # m; both legs seen as one segment (one behind the other)
    pair_distance: float = 0.45  # m; two legs nearer than this are one person
    leg_radius: float = 0.06    # m; the centre lies this far behind the seen surface
    pair_sigma: float = 0.08    # m; position uncertainty of a person from a leg pair
    single_sigma: float = 0.15  # m; from one leg only
    single_legs: bool = True    # report unpaired legs as people too
    max_range: float = 5.0      # m; farther legs (1-2 beams) cannot be told from clutter


def detect_legs(scan: LaserScan, params: LegParams | None = None) -> list[Detection]:
    """Person detections (robot frame, source "laser") found in one scan."""
    p = params or LegParams()
    points = _scan_points(scan)
    legs, both = [], []
    for run in _isolated_runs(scan, points, p):
        for centre, width in run:
            (legs if width <= p.max_width else both).append(centre)
    return _people(legs, scan.t, p) + [_detection(scan.t, xy, p.pair_sigma) for xy in both]


def _isolated_runs(scan: LaserScan, points: np.ndarray, p: LegParams):
    """Legs of each run of at most three adjacent small segments that stands out from both
    neighbours.

    Adjacent segments are one leg partly behind the other, possibly with a sliver (a leg edge
    too narrow to count on its own). A longer run of small segments is a wall seen at a
    grazing angle, whose range grows in steps from beam to beam."""
    runs: list[list] = []          # [start, end, legs, pieces]
    last_end = -1
    starts, ends = _segments(scan.ranges, p)
    centres, widths = _segment_geometry(points, scan, starts, ends, p)
    ranges = scan.ranges.tolist()       # plain floats: read one at a time below
    for start, end, centre, width in zip(starts.tolist(), ends.tolist(), centres.tolist(),
                                         widths.tolist()):
        if width > p.max_both_width or _is_hole(ranges, start, end, p.jump):
            last_end = -1
            continue
        if start != last_end:
            runs.append([start, end, [], 0])
        run = runs[-1]
        run[1], run[3] = end, run[3] + 1
        if width >= p.min_width:
            run[2].append(((centre[0], centre[1]), width))
        last_end = end
    for start, end, legs, pieces in runs:
        if legs and pieces <= 3 and _stands_out(ranges, start, end, p.contrast):
            yield legs


def _scan_points(scan: LaserScan) -> np.ndarray:
    ox, oy, _ = scan.origin
    ranges = np.where(np.isfinite(scan.ranges), scan.ranges, np.nan)
    points = np.empty((len(ranges), 2))
    points[:, 0] = ox + ranges * np.cos(scan.angles)
    points[:, 1] = oy + ranges * np.sin(scan.angles)
    return points


def _segments(ranges: np.ndarray, p: LegParams) -> tuple[np.ndarray, np.ndarray]:
    """Index ranges [start, end) of consecutive beams with hits and no range jump."""
    valid = np.isfinite(ranges) & (ranges <= p.max_range)
    cut = np.ones(len(ranges) + 1, dtype=bool)
    if len(ranges) > 1:
        kept = np.where(valid, ranges, 0.0)
        step = np.abs(kept[1:] - kept[:-1])          # np.diff's subtraction, without its wrapper
        cut[1:-1] = (step > p.jump) | ~(valid[1:] & valid[:-1])
    starts = np.flatnonzero(cut[:-1] & valid)
    cuts = np.flatnonzero(cut)                  # a segment ends at the first cut after its start
    return starts, cuts[np.searchsorted(cuts, starts, side="right")]


def _segment_geometry(points: np.ndarray, scan: LaserScan, starts: np.ndarray, ends: np.ndarray,
                      p: LegParams) -> tuple[np.ndarray, np.ndarray]:
    """Per segment: where the leg would stand (behind the seen surface) and how wide it is.

    Sums over each segment come from cumulative sums, so every segment costs the same few
    array operations at once (a scan has dozens of segments, most of them walls)."""
    if len(starts) == 0:
        return np.zeros((0, 2)), np.zeros(0)
    counts = (ends - starts).astype(float)
    finite = np.isfinite(scan.ranges)
    ranges_sum = np.concatenate(([0.0], np.cumsum(np.where(finite, scan.ranges, 0.0))))
    points_sum = np.zeros((len(points) + 1, 2))      # points are finite or NaN (no echo)
    np.cumsum(np.where(np.isnan(points), 0.0, points), axis=0, out=points_sum[1:])
    mean_range = (ranges_sum[ends] - ranges_sum[starts]) / counts
    n = len(scan.angles)
    if n >= 2:
        i = np.minimum(np.maximum(starts, 1), n - 1)
        beam_step = np.abs(scan.angles[i] - scan.angles[i - 1])
    else:
        beam_step = np.zeros(len(starts))
    span = points[ends - 1] - points[starts]
    widths = np.hypot(span[:, 0], span[:, 1]) + mean_range * beam_step
    centres = (points_sum[ends] - points_sum[starts]) / counts[:, None]
    ray = centres - np.asarray(scan.origin[:2], dtype=float)
    norm = np.hypot(ray[:, 0], ray[:, 1])
    away = norm > 1e-9
    if away.all():                              # the usual case: one step instead of masks
        centres += ray / norm[:, None] * p.leg_radius
    else:
        centres[away] += ray[away] / norm[away, None] * p.leg_radius
    return centres, widths


def _is_hole(ranges: list[float], start: int, end: int, jump: float) -> bool:
    """Beams between two nearer things (the wall seen between two legs)."""
    left = ranges[start - 1] if start > 0 else math.inf
    right = ranges[end] if end < len(ranges) else math.inf
    return left < ranges[start] - jump and right < ranges[end - 1] - jump


def _stands_out(ranges: list[float], start: int, end: int, contrast: float) -> bool:
    """The beams beside the run see something clearly behind it, or on one side clearly in
    front (an occluding leg). Not so the gap between two legs, whose beams reach the wall
    behind: that piece is farther than both its neighbours."""
    left = ranges[start - 1] if start > 0 else math.inf
    right = ranges[end] if end < len(ranges) else math.inf
    behind = [not math.isfinite(side) or side > own + contrast
              for side, own in ((left, ranges[start]), (right, ranges[end - 1]))]
    in_front = [side < own - contrast
                for side, own in ((left, ranges[start]), (right, ranges[end - 1]))]
    return any(behind) and all(b or f for b, f in zip(behind, in_front))


def _people(legs: list[tuple[float, float]], t: float, p: LegParams) -> list[Detection]:
    """Pair legs greedily, closest pairs first; midpoints of pairs, and lone legs if allowed."""
    pairs = sorted((math.dist(a, b), i, j) for i, a in enumerate(legs)
                   for j, b in enumerate(legs) if i < j)
    used: set[int] = set()
    people = []
    for gap, i, j in pairs:
        if gap >= p.pair_distance or i in used or j in used:
            continue
        used.update((i, j))
        mid = ((legs[i][0] + legs[j][0]) / 2, (legs[i][1] + legs[j][1]) / 2)
        people.append(_detection(t, mid, p.pair_sigma))
    if p.single_legs:
        people += [_detection(t, leg, p.single_sigma)
                   for k, leg in enumerate(legs) if k not in used]
    return people


def _detection(t: float, xy: tuple[float, float], sigma: float) -> Detection:
    return Detection(t=t, x=xy[0], y=xy[1], cov=_covariance(sigma), source="laser")


def _covariance(sigma: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """One covariance object per sigma: perception rotates each object once a tick
    (`skills.people.frames.detections_to_world`)."""
    cov = _COVARIANCES.get(sigma)
    if cov is None:
        var = sigma * sigma
        cov = _COVARIANCES[sigma] = ((var, 0.0), (0.0, var))
    return cov


_COVARIANCES: dict[float, tuple[tuple[float, float], tuple[float, float]]] = {}
