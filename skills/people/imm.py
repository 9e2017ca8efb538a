"""An interacting-multiple-model filter of a person who stops and goes: walking (constant
velocity) and standing (velocity held at zero), mixed by filterpy's IMMEstimator.

A constant-velocity filter overshoots when someone stops and lags when they start; the IMM
switches between the two models within a few frames. It costs several times a single filter,
so the tracker uses it only when `TrackerParams.model == "imm"` (see docs/tracking.md for
whether it pays).
"""
from __future__ import annotations

import math

import numpy as np
from skills.people.kalman import IMMEstimator, KalmanFilter

from skills.people import motion_model

STAND_SWAY = 0.1        # m/s; a standing person's position still wanders this much
STAY_PROBABILITY = 0.95  # per 0.1 s frame, of keeping the current mode
LOG_2PI = math.log(2.0 * math.pi)   # normalising constant of a 2-D Gaussian


def standing_transition() -> np.ndarray:
    """F of the standing model: position stays, velocity is forgotten (set to zero)."""
    return np.diag([1.0, 1.0, 0.0, 0.0])


def standing_noise(dt: float) -> np.ndarray:
    """Q of the standing model: a slow random walk of the position, a tiny velocity."""
    sway = STAND_SWAY ** 2 * dt
    return np.diag([sway, sway, 1e-4, 1e-4])


class _PositionFilter(KalmanFilter):
    """filterpy's KalmanFilter, with the log-likelihood of a 2-D innovation in closed form.

    The IMM weighs its models by this likelihood every update; filterpy computes it through
    scipy's general multivariate normal, which costs more than the rest of the update."""

    @property
    def log_likelihood(self) -> float:
        if self._log_likelihood is None:
            (a, b), (c, d) = self.S.tolist()
            det = a * d - b * c
            y0, y1 = self.y.ravel().tolist()
            d2 = (d * y0 * y0 - (b + c) * y0 * y1 + a * y1 * y1) / det
            self._log_likelihood = -0.5 * (d2 + math.log(det)) - LOG_2PI
        return self._log_likelihood


def make_imm(x0: np.ndarray, p0: np.ndarray, inv) -> IMMEstimator:
    """An IMM of [walking, standing], both started at state x0 (4, 1) and covariance p0."""
    filters = []
    for _ in range(2):
        kf = _PositionFilter(dim_x=4, dim_z=2)
        kf.x, kf.P, kf.H, kf.inv = x0.copy(), p0.copy(), motion_model.H, inv
        filters.append(kf)
    stay, switch = STAY_PROBABILITY, 1.0 - STAY_PROBABILITY
    return IMMEstimator(filters, mu=np.array([0.5, 0.5]),
                        M=np.array([[stay, switch], [switch, stay]]))


def predict(imm: IMMEstimator, walk: tuple[np.ndarray, np.ndarray],
            stand: tuple[np.ndarray, np.ndarray]) -> None:
    """Predict with (F, Q) of the walking and of the standing model for this time step."""
    walking, standing = imm.filters
    walking.F, walking.Q = walk
    standing.F, standing.Q = stand
    imm.predict()


def update(imm: IMMEstimator, z: np.ndarray, r: np.ndarray) -> None:
    for kf in imm.filters:
        kf.R = r
    imm.update(z)
