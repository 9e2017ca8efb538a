"""Which detection belongs to which track: Mahalanobis gating and a global assignment.

All pairwise innovation covariances and distances are computed at once with numpy (2x2
inverses in closed form), then scipy's Hungarian solver picks the assignment of least total
cost. The cost is the negative log-likelihood up to a constant, d^2 + ln det S, so an
uncertain (coasting) track does not win a detection merely because its gate is wide.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

INFEASIBLE = 1e9   # cost of a pair outside the gate; never chosen over leaving both unassigned


def inverse_2x2(m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverses and determinants of a stack (..., 2, 2) of 2x2 matrices."""
    a, b, c, d = m[..., 0, 0], m[..., 0, 1], m[..., 1, 0], m[..., 1, 1]
    det = a * d - b * c
    inv = np.empty_like(m)
    inv[..., 0, 0] = d / det
    inv[..., 0, 1] = -b / det
    inv[..., 1, 0] = -c / det
    inv[..., 1, 1] = a / det
    return inv, det


def mahalanobis_sq(track_xy: np.ndarray, track_cov: np.ndarray,
                   det_xy: np.ndarray, det_cov: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Squared Mahalanobis distances d^2 (n, m) of every detection from every predicted track,
    with S = P_track + R_detection, and ln det S (n, m)."""
    s = track_cov[:, None, :, :] + det_cov[None, :, :, :]
    s_inv, det = inverse_2x2(s)
    y = det_xy[None, :, :] - track_xy[:, None, :]
    d2 = (y[..., 0] * (s_inv[..., 0, 0] * y[..., 0] + s_inv[..., 0, 1] * y[..., 1])
          + y[..., 1] * (s_inv[..., 1, 0] * y[..., 0] + s_inv[..., 1, 1] * y[..., 1]))
    return d2, np.log(det)


def gated_cost(d2: np.ndarray, log_det: np.ndarray, gate: float,
               out_of_reach: np.ndarray | None = None) -> np.ndarray:
    """Assignment cost d^2 + ln det S, INFEASIBLE outside the gate d^2 > gate and where
    `out_of_reach` (the same shape) is True."""
    cost = d2 + log_det
    cost[d2 > gate] = INFEASIBLE
    if out_of_reach is not None:
        cost[out_of_reach] = INFEASIBLE
    return cost


def unambiguous_pairs(track_xy: np.ndarray, det_xy: np.ndarray, limit: float
                      ) -> list[tuple[int, int]]:
    """Pairs (track, detection) at most `limit` metres apart where neither has anything else
    within `limit`: the only track near the detection, the only detection near the track."""
    if not len(track_xy) or not len(det_xy):
        return []
    gap = track_xy[:, None, :] - det_xy[None, :, :]
    near = np.hypot(gap[..., 0], gap[..., 1]) <= limit
    alone = near & (near.sum(axis=0) == 1)[None, :] & (near.sum(axis=1) == 1)[:, None]
    return [(int(r), int(c)) for r, c in zip(*np.nonzero(alone))]


def assign(cost: np.ndarray) -> tuple[list[tuple[int, int]], list[int], list[int]]:
    """Globally optimal pairs (track, detection) among feasible ones, plus the unassigned
    tracks and detections."""
    n, m = cost.shape
    pairs: list[tuple[int, int]] = []
    if n and m:
        rows, cols = linear_sum_assignment(cost)
        pairs = [(int(r), int(c)) for r, c in zip(rows, cols) if cost[r, c] < INFEASIBLE]
    used_tracks = {r for r, _ in pairs}
    used_dets = {c for _, c in pairs}
    return (pairs, [i for i in range(n) if i not in used_tracks],
            [j for j in range(m) if j not in used_dets])
