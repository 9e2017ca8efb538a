"""Several detections of one person in one frame (camera and laser both see them) become one.

Two independent measurements of the same position, fused by their information (inverse
covariance), give exactly the Kalman update that two sequential updates would give, at half
the cost, and they can no longer start a second, duplicate track.
"""
from __future__ import annotations

import numpy as np


def fuse_close_detections(xy: np.ndarray, cov: np.ndarray, merge_distance: float,
                          flags: np.ndarray | None = None
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Merge detections closer than `merge_distance` (m) to each other.

    People's centres are at least about 0.4 m apart, so closer detections are taken as one
    person. Clusters are formed by linking close pairs; each cluster is fused by the
    information-weighted mean. `flags` (bool per detection, e.g. "may confirm a track") are
    or-ed within a cluster. Returns (xy, cov, flags), one row per cluster, in the order of
    each cluster's first detection; the inputs themselves when nothing merges.
    """
    m = len(xy)
    if flags is None:
        flags = np.ones(m, dtype=bool)
    if m < 2 or merge_distance <= 0.0:
        return xy, cov, flags
    diff = xy[:, None, :] - xy[None, :, :]
    dist_sq = diff[..., 0] ** 2 + diff[..., 1] ** 2
    close_i, close_j = np.nonzero(dist_sq < merge_distance ** 2)
    upper = close_i < close_j
    if not upper.any():
        return xy, cov, flags
    cluster = _clusters(m, close_i[upper].tolist(), close_j[upper].tolist())
    return _fuse_clusters(xy, cov, flags, cluster)


def _clusters(m: int, firsts: list[int], seconds: list[int]) -> np.ndarray:
    """Cluster number (0, 1, ... in order of first member) of each detection, by union-find
    over the linked pairs."""
    parent = list(range(m))
    for i, j in zip(firsts, seconds):
        root_i, root_j = _root(parent, i), _root(parent, j)
        if root_i != root_j:
            parent[max(root_i, root_j)] = min(root_i, root_j)
    numbers: dict[int, int] = {}
    return np.array([numbers.setdefault(_root(parent, i), len(numbers)) for i in range(m)])


def _root(parent: list[int], i: int) -> int:
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


def _fuse_clusters(xy: np.ndarray, cov: np.ndarray, flags: np.ndarray,
                   cluster: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Information-weighted mean per cluster: C = (sum C_i^-1)^-1, x = C sum C_i^-1 x_i."""
    k = int(cluster.max()) + 1
    a, b, c = cov[:, 0, 0], cov[:, 0, 1], cov[:, 1, 1]
    det = a * c - b * b
    ia, ib, ic = c / det, -b / det, a / det               # information of each detection
    wx, wy = ia * xy[:, 0] + ib * xy[:, 1], ib * xy[:, 0] + ic * xy[:, 1]
    sa, sb, sc, swx, swy = (np.bincount(cluster, weights=w, minlength=k)
                            for w in (ia, ib, ic, wx, wy))
    det = sa * sc - sb * sb
    fa, fb, fc = sc / det, -sb / det, sa / det
    fused_xy = np.empty((k, 2))
    fused_xy[:, 0], fused_xy[:, 1] = fa * swx + fb * swy, fb * swx + fc * swy
    fused_cov = np.empty((k, 2, 2))
    fused_cov[:, 0, 0], fused_cov[:, 0, 1], fused_cov[:, 1, 0], fused_cov[:, 1, 1] = fa, fb, fb, fc
    fused_flags = np.zeros(k, dtype=bool)
    fused_flags[cluster[flags]] = True
    return fused_xy, fused_cov, fused_flags
