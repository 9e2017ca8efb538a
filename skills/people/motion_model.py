"""The constant-velocity motion model of a walking person, state [x, y, vx, vy].

Velocity changes are modelled as white-noise acceleration with spectral density `q`
(m^2/s^3): people start, stop and turn, and `q` says how quickly the filter lets them.
"""
from __future__ import annotations

import numpy as np

# Measurement matrix: detectors measure position only.
H = np.array([[1.0, 0.0, 0.0, 0.0],
              [0.0, 1.0, 0.0, 0.0]])


def transition(dt: float) -> np.ndarray:
    """F: positions advance by velocity times dt; velocities stay."""
    return np.array([[1.0, 0.0, dt, 0.0],
                     [0.0, 1.0, 0.0, dt],
                     [0.0, 0.0, 1.0, 0.0],
                     [0.0, 0.0, 0.0, 1.0]])


def process_noise(dt: float, q: float) -> np.ndarray:
    """Q of the continuous white-noise acceleration model, discretised over dt."""
    a, b, c = q * dt ** 3 / 3.0, q * dt ** 2 / 2.0, q * dt
    return np.array([[a, 0.0, b, 0.0],
                     [0.0, a, 0.0, b],
                     [b, 0.0, c, 0.0],
                     [0.0, b, 0.0, c]])
