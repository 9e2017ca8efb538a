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
    person. Clusters are formed greedily by the closest pairs; each cluster is fused by the
    information-weighted mean. `flags` (bool per detection, e.g. "may confirm a track") are
    or-ed within a cluster. Returns new (xy, cov, flags) arrays: the detections left alone
    first, in their order, then the fused ones.
    """
    m = len(xy)
    if flags is None:
        flags = np.ones(m, dtype=bool)
    if m < 2 or merge_distance <= 0.0:
        return xy, cov, flags
    diff = xy[:, None, :] - xy[None, :, :]
    dist = np.hypot(diff[..., 0], diff[..., 1])
    close_i, close_j = np.nonzero(np.triu(dist < merge_distance, k=1))
    if close_i.size == 0:
        return xy, cov, flags
    parent = {int(i): int(i) for i in np.concatenate((close_i, close_j))}
    for k in np.argsort(dist[close_i, close_j], kind="stable"):
        root_i, root_j = _root(parent, int(close_i[k])), _root(parent, int(close_j[k]))
        if root_i != root_j:
            parent[root_j] = root_i
    groups: dict[int, list[int]] = {}
    for index in sorted(parent):
        groups.setdefault(_root(parent, index), []).append(index)
    alone = np.ones(m, dtype=bool)
    alone[list(parent)] = False
    fused = [_fuse(xy[g], cov[g]) for g in groups.values()]
    out_xy = np.vstack([xy[alone]] + [f[0][None, :] for f in fused])
    out_cov = np.concatenate([cov[alone]] + [f[1][None, :, :] for f in fused])
    out_flags = np.concatenate([flags[alone], [bool(flags[g].any()) for g in groups.values()]])
    return out_xy, out_cov, out_flags


def _root(parent: dict[int, int], i: int) -> int:
    while parent[i] != i:
        i = parent[i]
    return i


def _fuse(xy: np.ndarray, cov: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    info = np.linalg.inv(cov)
    fused_cov = np.linalg.inv(info.sum(axis=0))
    fused_xy = fused_cov @ np.einsum("kij,kj->i", info, xy)
    return fused_xy, fused_cov
