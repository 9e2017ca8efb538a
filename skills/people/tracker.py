"""A multi-person tracker: one filterpy Kalman filter per person, in the world frame.

Each call to `update` is one frame: predict every track to the frame's time, fuse duplicate
detections, gate and assign detections to tracks globally, update the assigned filters, start
tentative tracks from the rest, and move tracks along their life cycle
tentative -> confirmed -> lost -> deleted. Detections must already be in the world frame
(see `skills.people.frames`): that transform is the compensation for the robot's own motion.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from skills.people.kalman import LeanKalmanFilter, predict_all, update_all

from skills.people import imm, motion_model
from skills.people.association import (assign, gated_cost, inverse_2x2, mahalanobis_sq,
                                       unambiguous_pairs)
from skills.people.fusion import fuse_close_detections
from skills.people.track import CONFIRMED, LOST, TENTATIVE, Track

# x, y (m, world frame), 2x2 covariance (m^2), and optionally the source ("camera", "laser")
# and the appearance (robots.devices.Detection.appearance)
WorldDetection = (tuple[float, float, np.ndarray] | tuple[float, float, np.ndarray, str]
                  | tuple[float, float, np.ndarray, str, tuple[float, ...] | None])


@dataclass(frozen=True)
class TrackerParams:
    """Tuning of the tracker; times are in seconds so the tick rate can change."""
    accel_noise: float = 0.5          # q of the white-noise acceleration model, m^2/s^3
    initial_speed_sigma: float = 1.0  # m/s, velocity prior of a new track (walking pace)
    gate: float = 18.4                # d^2 limit; chi-square 2 dof: 13.8 = 99.9 %, 18.4 = 99.99 %
    merge_distance: float = 0.3       # m; same-frame detections closer than this are one person
    confirm_hits: int = 3             # detections needed before a track is believed
    # Sources whose detections may confirm a track; None: all. With ("camera",) laser legs
    # update tracks but cannot make a door jamb a person. Detections without a source count.
    confirming_sources: tuple[str, ...] | None = None
    confirming_hits: int = 2          # of the confirm_hits, how many from confirming sources
    tentative_timeout: float = 0.25   # s unseen after which a tentative track is dropped
    lost_after: float = 0.35          # s unseen after which a confirmed track is reported lost
    delete_after: float = 1.5         # s unseen after which a lost track is deleted
    max_dt: float = 1.0               # s; longer gaps are predicted in steps no longer than this
    model: str = "cv"                 # "cv": constant velocity; "imm": walking + standing IMM
    min_variance: float = 1e-4        # m^2 (1 cm); added to detection covariances below it
    # How far from its prediction a detection may still be a track's, in metres, whatever
    # the filter's covariance says: reach_base + reach_accel * unseen^2 / 2 (a person veering
    # off their walk at reach_accel m/s^2 for the time unseen, plus the detector's error).
    # A track coasting for a second has a covariance whose 99.99 % gate spans ~3 m.
    reach_base: float = 0.8           # m
    reach_accel: float = 1.0          # m/s^2
    # A detection no track's gate took, this near (m) a track that took none although it was
    # seen the frame before, and near no other track, is that track's person, not a new one:
    # a standing person's first detections can teach the filter a walking pace out of noise,
    # and its prediction then leaves the gate, frame after frame, while a second track starts
    # on the person. Nearer than people stand; a track unseen for longer (someone hidden) is
    # left to its gate, and where two tracks are near the detection, nobody guesses.
    leftover_reach: float = 0.5       # m


class _TrackState:
    """A track's filter and its life-cycle counters (internal)."""

    __slots__ = ("id", "kf", "hits", "confirming_hits", "born", "confirmed_at", "last_seen",
                 "status", "appearance", "appearance_t", "confirmed_seen")

    def __init__(self, track_id: int, t: float, xy: np.ndarray, cov: np.ndarray,
                 confirming: bool, params: TrackerParams) -> None:
        x0 = np.array([[xy[0]], [xy[1]], [0.0], [0.0]])
        p0 = np.zeros((4, 4))
        p0[:2, :2] = cov
        p0[2, 2] = p0[3, 3] = params.initial_speed_sigma ** 2
        if params.model == "imm":
            kf = imm.make_imm(x0, p0, inverse_2x2_single)
        else:
            kf = LeanKalmanFilter(dim_x=4, dim_z=2)
            kf.x, kf.P, kf.H, kf.inv = x0, p0, motion_model.H, inverse_2x2_single
        self.id = track_id
        self.kf = kf
        self.hits = 1
        self.confirming_hits = int(confirming)
        self.born = t
        self.confirmed_at: float | None = None
        self.last_seen = t
        self.status = TENTATIVE
        self.appearance: tuple[float, ...] | None = None
        self.appearance_t: float | None = None
        self.confirmed_seen: float | None = t if confirming else None

    def snapshot(self) -> Track:
        x, y, vx, vy = self.kf.x.ravel().tolist()
        return Track(id=self.id, x=x, y=y, vx=vx, vy=vy, cov=self.kf.P[:2, :2].copy(),
                     status=self.status,
                     born=self.born, confirmed_at=self.confirmed_at, last_seen=self.last_seen,
                     appearance=self.appearance, appearance_t=self.appearance_t,
                     confirmed_seen=self.confirmed_seen)


class PeopleTracker:
    """Tracks people from per-frame world-frame detections; `update` once per tick."""

    def __init__(self, params: TrackerParams | None = None) -> None:
        self.params = params or TrackerParams()
        if self.params.model not in ("cv", "imm"):
            raise ValueError(f"TrackerParams.model = {self.params.model!r}; "
                             "allowed: 'cv' (constant velocity), 'imm' (walking + standing)")
        self._tracks: list[_TrackState] = []
        self._ids = itertools.count(1)
        self._t: float | None = None

    @property
    def time(self) -> float | None:
        """Time of the last frame, or None before the first."""
        return self._t

    def update(self, t: float, detections: list[WorldDetection]) -> list[Track]:
        """Process the frame at time `t` and return the tracks that are not deleted.

        A ValueError (a frame older than the last, a non-finite detection) leaves the tracker
        as it was."""
        if self._t is not None and t < self._t:
            raise ValueError(f"frame at t={t} is older than the previous one at t={self._t}")
        xy, cov, confirming = _as_arrays(detections, self.params.confirming_sources)
        cov = _with_variance_floor(cov, self.params.min_variance)
        self._predict(t)
        seen_xy = xy
        xy, cov, confirming = fuse_close_detections(xy, cov, self.params.merge_distance,
                                                    confirming)
        looks = _appearances(detections, seen_xy, xy, self.params.merge_distance)
        pairs, _, new_dets = self._associate(xy, cov, t)
        self._update_filters(pairs, xy, cov)
        for i, j in pairs:
            self._correct(self._tracks[i], t, bool(confirming[j]), looks[j])
        for j in new_dets:
            state = _TrackState(next(self._ids), t, xy[j], cov[j], bool(confirming[j]),
                                self.params)
            if looks[j] is not None:
                state.appearance, state.appearance_t = looks[j], t
            self._tracks.append(state)
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
            if self.params.model == "imm":
                stand = (imm.standing_transition(), imm.standing_noise(dt))
                for state in self._tracks:
                    imm.predict(state.kf, (f, q), stand)
            else:
                predict_all([state.kf for state in self._tracks], f, q)
            remaining -= dt

    def _associate(self, xy: np.ndarray, cov: np.ndarray, t: float):
        n, m = len(self._tracks), len(xy)
        if n == 0 or m == 0:
            return [], list(range(n)), list(range(m))
        track_xy = np.array([s.kf.x[:2, 0] for s in self._tracks])
        track_cov = np.array([s.kf.P[:2, :2] for s in self._tracks])
        d2, log_det = mahalanobis_sq(track_xy, track_cov, xy, cov)
        pairs, tracks_left, dets_left = assign(gated_cost(d2, log_det, self.params.gate,
                                                          self._out_of_reach(track_xy, xy, t)))
        paired = self._leftovers_paired(tracks_left, dets_left, track_xy, xy)
        if not paired:
            return pairs, tracks_left, dets_left
        took_track, took_det = {i for i, _ in paired}, {j for _, j in paired}
        return (pairs + paired, [i for i in tracks_left if i not in took_track],
                [j for j in dets_left if j not in took_det])

    def _leftovers_paired(self, tracks_left: list[int], dets_left: list[int],
                          track_xy: np.ndarray, xy: np.ndarray) -> list[tuple[int, int]]:
        """Leftover detections that are, unambiguously, a leftover track's seen the frame
        before (`TrackerParams.leftover_reach`): the only track within reach of the detection,
        and the only leftover detection within reach of it."""
        if not tracks_left or not dets_left:
            return []
        just_seen = {i for i in tracks_left if self._tracks[i].last_seen == self._t}
        if not just_seen:
            return []
        pairs = unambiguous_pairs(track_xy, xy[dets_left], self.params.leftover_reach)
        return [(i, dets_left[j]) for i, j in pairs if i in just_seen]

    def _out_of_reach(self, track_xy: np.ndarray, xy: np.ndarray, t: float) -> np.ndarray:
        """(n, m) True where a detection is farther from a track's prediction than its person
        can have got to (`TrackerParams.reach_base`, `reach_accel`). Without it a lost track
        took over another person's legs 1.8 m from where it coasted (a look-alike's track
        standing still jumped onto the customer, whose own track had gone off with a passer-by
        the same way: bench_follow lookalike seed 2, PERSES, issue 23)."""
        p = self.params
        unseen = np.array([t - s.last_seen for s in self._tracks])
        reach = p.reach_base + 0.5 * p.reach_accel * unseen ** 2
        gap = track_xy[:, None, :] - xy[None, :, :]
        return np.hypot(gap[..., 0], gap[..., 1]) > reach[:, None]

    def _update_filters(self, pairs: list[tuple[int, int]], xy: np.ndarray,
                        cov: np.ndarray) -> None:
        """Each paired track's filter takes its detection (the cv filters all at once)."""
        if not pairs:
            return
        if self.params.model == "imm":
            for i, j in pairs:
                imm.update(self._tracks[i].kf, xy[j].reshape(2, 1), cov[j])
            return
        tracks, dets = zip(*pairs)
        update_all([self._tracks[i].kf for i in tracks], xy[list(dets), :, None],
                   cov[list(dets)], motion_model.H, _inverses)

    def _correct(self, state: _TrackState, t: float, confirming: bool,
                 appearance: tuple[float, ...] | None = None) -> None:
        """A track's life cycle after its filter took a detection."""
        if appearance is not None:
            state.appearance, state.appearance_t = appearance, t
        state.hits += 1
        state.confirming_hits += confirming
        state.last_seen = t
        if confirming:
            state.confirmed_seen = t
        if state.status == TENTATIVE:
            if self._may_confirm(state):
                state.status, state.confirmed_at = CONFIRMED, t
        else:
            state.status = CONFIRMED

    def _may_confirm(self, state: _TrackState) -> bool:
        p = self.params
        needed = p.confirming_hits if p.confirming_sources is not None else 0
        return state.hits >= p.confirm_hits and state.confirming_hits >= min(needed,
                                                                             p.confirm_hits)

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


def _with_variance_floor(cov: np.ndarray, floor: float) -> np.ndarray:
    """Covariances too small to invert safely (a noise-free simulated detector, a rounding
    to zero) get `floor` added to the diagonal; the others are left as they are."""
    det = cov[:, 0, 0] * cov[:, 1, 1] - cov[:, 0, 1] * cov[:, 1, 0]
    small = (cov[:, 0, 0] < floor) | (cov[:, 1, 1] < floor) | (det < floor * floor)
    if small.any():
        cov = cov.copy()
        cov[small] += np.eye(2) * floor
    return cov


def inverse_2x2_single(m: np.ndarray) -> np.ndarray:
    """Closed-form inverse of the 2x2 innovation covariance, for filterpy's `inv` hook:
    a third of numpy.linalg.inv's cost on matrices this small."""
    a, b, c, d = m.ravel().tolist()
    det = a * d - b * c
    return np.array([[d / det, -b / det], [-c / det, a / det]])


def _inverses(m: np.ndarray) -> np.ndarray:
    """`inverse_2x2_single` of each of a stack of 2x2 matrices (the same floats)."""
    return inverse_2x2(m)[0]


def _appearances(detections: list[WorldDetection], seen_xy: np.ndarray, fused_xy: np.ndarray,
                 merge_distance: float) -> list[tuple[float, ...] | None]:
    """Per fused detection, the appearance of the nearest detection that carries one (the
    camera's, when the laser saw the same person), or None."""
    seen = seen_xy.tolist()      # plain floats: the same differences, squares and sums
    looks = [(seen[k], d[4]) for k, d in enumerate(detections)
             if len(d) > 4 and d[4] is not None]
    if not looks:
        return [None] * len(fused_xy)
    result: list[tuple[float, ...] | None] = []
    for fx, fy in fused_xy.tolist():
        (sx, sy), look = min(looks, key=lambda xy_look: (xy_look[0][0] - fx) ** 2
                             + (xy_look[0][1] - fy) ** 2)
        near = math.hypot(sx - fx, sy - fy) <= merge_distance
        result.append(tuple(look) if near else None)
    return result


def _as_arrays(detections: list[WorldDetection], confirming_sources: tuple[str, ...] | None
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions (m, 2), covariances (m, 2, 2) and whether each detection may confirm."""
    if not detections:
        return np.zeros((0, 2)), np.zeros((0, 2, 2)), np.zeros(0, dtype=bool)
    xy = np.array([(d[0], d[1]) for d in detections], dtype=float)
    cov = np.array([d[2] for d in detections], dtype=float)
    if cov.shape[1:] != (2, 2):
        raise ValueError(f"detection covariances must be 2x2; got shape {cov.shape[1:]}")
    broken = ~(np.isfinite(xy).all(axis=1) & np.isfinite(cov).all(axis=(1, 2)))
    if broken.any():
        index = int(np.flatnonzero(broken)[0])
        raise ValueError(f"detection {index} of this frame is not finite: {detections[index]!r}; "
                         "a detector must leave out what it did not measure")
    if confirming_sources is None:
        return xy, cov, np.ones(len(detections), dtype=bool)
    confirming = np.array([len(d) < 4 or d[3] in confirming_sources for d in detections])
    return xy, cov, confirming
