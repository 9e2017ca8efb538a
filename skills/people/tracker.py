"""A multi-person tracker: one filterpy Kalman filter per person, in the world frame.

Each call to `update` is one frame: predict every track to the frame's time, fuse duplicate
detections, gate and assign detections to tracks globally, update the assigned filters, start
tentative tracks from the rest, and move tracks along their life cycle
tentative -> confirmed -> lost -> deleted. Detections must already be in the world frame
(see `skills.people.frames`): that transform is the compensation for the robot's own motion.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from filterpy.kalman import KalmanFilter

from skills.people import motion_model
from skills.people.association import assign, gated_cost, mahalanobis_sq
from skills.people.fusion import fuse_close_detections
from skills.people.track import CONFIRMED, LOST, TENTATIVE, Track

WorldDetection = tuple[float, float, np.ndarray]   # x, y (m, world frame), 2x2 covariance (m^2)


@dataclass(frozen=True)
class TrackerParams:
    """Tuning of the tracker; times are in seconds so the tick rate can change."""
    accel_noise: float = 0.5          # q of the white-noise acceleration model, m^2/s^3
    initial_speed_sigma: float = 1.0  # m/s, velocity prior of a new track (walking pace)
    gate: float = 18.4                # d^2 threshold; chi-square, 2 dof: 13.8 = 99.9 %, 18.4 = 99.99 %
    merge_distance: float = 0.3       # m; same-frame detections closer than this are one person
    confirm_hits: int = 3             # detections needed before a track is believed
    tentative_timeout: float = 0.25   # s unseen after which a tentative track is dropped
    lost_after: float = 0.35          # s unseen after which a confirmed track is reported lost
    delete_after: float = 1.5         # s unseen after which a lost track is deleted
    max_dt: float = 1.0               # s; longer gaps are predicted in steps no longer than this


class _TrackState:
    """A track's filter and its life-cycle counters (internal)."""

    __slots__ = ("id", "kf", "hits", "born", "confirmed_at", "last_seen", "status")

    def __init__(self, track_id: int, t: float, xy: np.ndarray, cov: np.ndarray,
                 params: TrackerParams) -> None:
        kf = KalmanFilter(dim_x=4, dim_z=2)
        kf.x = np.array([[xy[0]], [xy[1]], [0.0], [0.0]])
        kf.P = np.zeros((4, 4))
        kf.P[:2, :2] = cov
        kf.P[2, 2] = kf.P[3, 3] = params.initial_speed_sigma ** 2
        kf.H = motion_model.H
        kf.inv = inverse_2x2_single
        self.id = track_id
        self.kf = kf
        self.hits = 1
        self.born = t
        self.confirmed_at: float | None = None
        self.last_seen = t
        self.status = TENTATIVE

    def snapshot(self) -> Track:
        x, y, vx, vy = self.kf.x.ravel().tolist()
        return Track(id=self.id, x=x, y=y, vx=vx, vy=vy, cov=self.kf.P[:2, :2].copy(),
                     status=self.status,
                     born=self.born, confirmed_at=self.confirmed_at, last_seen=self.last_seen)


class PeopleTracker:
    """Tracks people from per-frame world-frame detections; `update` once per tick."""

    def __init__(self, params: TrackerParams | None = None) -> None:
        self.params = params or TrackerParams()
        self._tracks: list[_TrackState] = []
        self._ids = itertools.count(1)
        self._t: float | None = None

    @property
    def time(self) -> float | None:
        """Time of the last frame, or None before the first."""
        return self._t

    def update(self, t: float, detections: list[WorldDetection]) -> list[Track]:
        """Process the frame at time `t` and return the tracks that are not deleted."""
        if self._t is not None and t < self._t:
            raise ValueError(f"frame at t={t} is older than the previous one at t={self._t}")
        self._predict(t)
        xy, cov = _as_arrays(detections)
        xy, cov = fuse_close_detections(xy, cov, self.params.merge_distance)
        pairs, _, new_dets = self._associate(xy, cov)
        for i, j in pairs:
            self._correct(self._tracks[i], t, xy[j], cov[j])
        for j in new_dets:
            self._tracks.append(_TrackState(next(self._ids), t, xy[j], cov[j], self.params))
        self._age(t)
        self._t = t
        return self.tracks()

    def tracks(self) -> list[Track]:
        """Snapshots of the current (non-deleted) tracks."""
        return [state.snapshot() for state in self._tracks]

    def _predict(self, t: float) -> None:
        if self._t is None or t == self._t or not self._tracks:
            return
        remaining = t - self._t
        while remaining > 1e-12:
            dt = min(remaining, self.params.max_dt)
            f = motion_model.transition(dt)
            q = motion_model.process_noise(dt, self.params.accel_noise)
            for state in self._tracks:
                state.kf.predict(F=f, Q=q)
            remaining -= dt

    def _associate(self, xy: np.ndarray, cov: np.ndarray):
        n, m = len(self._tracks), len(xy)
        if n == 0 or m == 0:
            return [], list(range(n)), list(range(m))
        track_xy = np.array([s.kf.x[:2, 0] for s in self._tracks])
        track_cov = np.array([s.kf.P[:2, :2] for s in self._tracks])
        d2, log_det = mahalanobis_sq(track_xy, track_cov, xy, cov)
        return assign(gated_cost(d2, log_det, self.params.gate))

    def _correct(self, state: _TrackState, t: float, xy: np.ndarray, cov: np.ndarray) -> None:
        state.kf.update(xy.reshape(2, 1), R=cov, H=motion_model.H)
        state.hits += 1
        state.last_seen = t
        if state.status == TENTATIVE and state.hits >= self.params.confirm_hits:
            state.confirmed_at = t
        if state.status != TENTATIVE or state.hits >= self.params.confirm_hits:
            state.status = CONFIRMED

    def _age(self, t: float) -> None:
        p = self.params
        kept = []
        for state in self._tracks:
            unseen = t - state.last_seen
            if state.status == TENTATIVE:
                if unseen > p.tentative_timeout + 1e-9:
                    continue
            elif unseen > p.delete_after + 1e-9:
                continue
            elif unseen > p.lost_after + 1e-9:
                state.status = LOST
            kept.append(state)
        self._tracks = kept


def inverse_2x2_single(m: np.ndarray) -> np.ndarray:
    """Closed-form inverse of the 2x2 innovation covariance, for filterpy's `inv` hook:
    a third of numpy.linalg.inv's cost on matrices this small."""
    a, b, c, d = m.ravel().tolist()
    det = a * d - b * c
    return np.array([[d / det, -b / det], [-c / det, a / det]])


def _as_arrays(detections: list[WorldDetection]) -> tuple[np.ndarray, np.ndarray]:
    if not detections:
        return np.zeros((0, 2)), np.zeros((0, 2, 2))
    xy = np.array([(d[0], d[1]) for d in detections], dtype=float)
    cov = np.array([np.asarray(d[2], dtype=float) for d in detections])
    return xy, cov
