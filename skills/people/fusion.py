"""Several detections of one person in one frame (camera and laser both see them) become one.

Two independent measurements of the same position, fused by their information (inverse
covariance), give exactly the Kalman update that two sequential updates would give, at half
the cost, and they can no longer start a second, duplicate track.
"""
from __future__ import annotations

import numpy as np


def fuse_close_detections(xy: np.ndarray, cov: np.ndarray,
                          merge_distance: float) -> tuple[np.ndarray, np.ndarray]:
    """Merge detections closer than `merge_distance` (m) to each other.

    People's centres are at least about 0.4 m apart, so closer detections are taken as one
    person. Clusters are formed greedily by the closest pairs; each cluster is fused by the
    information-weighted mean. Returns new (xy, cov) arrays.
    """
    m = len(xy)
    if m < 2 or merge_distance <= 0.0:
        return xy, cov
    diff = xy[:, None, :] - xy[None, :, :]
    dist = np.hypot(diff[..., 0], diff[..., 1])
    close_i, close_j = np.nonzero(np.triu(dist < merge_distance, k=1))
    if close_i.size == 0:
        return xy, cov
    cluster = list(range(m))
    for k in np.argsort(dist[close_i, close_j], kind="stable"):
        i, j = int(close_i[k]), int(close_j[k])
        root_i, root_j = _root(cluster, i), _root(cluster, j)
        if root_i != root_j:
            cluster[root_j] = root_i
    roots = [_root(cluster, i) for i in range(m)]
    groups: dict[int, list[int]] = {}
    for index, root in enumerate(roots):
        groups.setdefault(root, []).append(index)
    fused = [_fuse(xy[g], cov[g]) for g in groups.values()]
    return np.array([f[0] for f in fused]), np.array([f[1] for f in fused])


def _root(cluster: list[int], i: int) -> int:
    while cluster[i] != i:
        i = cluster[i]
    return i


def _fuse(xy: np.ndarray, cov: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if len(xy) == 1:
        return xy[0], cov[0]
    info = np.linalg.inv(cov)
    fused_cov = np.linalg.inv(info.sum(axis=0))
    fused_xy = fused_cov @ np.einsum("kij,kj->i", info, xy)
    return fused_xy, fused_cov
