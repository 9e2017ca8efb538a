"""filterpy's Kalman filters, imported without importing scipy.stats.

Why: `import filterpy` imports `filterpy.stats`, which imports `scipy.stats`, and SciPy 1.17
rewrites several hundred docstrings while scipy.stats is imported: about 1 s of CPU in every
process that tracks people, half of what `interbot run` or `interbot check` costs before its
first tick. Our filters never call `filterpy.stats` (the tracker's gating and the IMM's
likelihood are computed in closed form, `skills/people/imm.py`), and filterpy's Kalman filters
take only `logpdf` from it, so `filterpy.stats` is registered first as a stand-in module that
imports the real one the first time any of its names is used. Everything of filterpy keeps
working; only what nobody uses is not paid for.
"""
from __future__ import annotations

import importlib.util
import sys
import types
from pathlib import Path

STATS = "filterpy.stats"


def _stand_in_for_filterpy_stats() -> None:
    """Put a stand-in for `filterpy.stats` into sys.modules, unless it is imported already."""
    if STATS in sys.modules:
        return
    top = importlib.util.find_spec("filterpy")       # finds the package without running it
    if top is None or not top.submodule_search_locations:
        return                                        # filterpy missing: the import below says so
    folder = Path(next(iter(top.submodule_search_locations))) / "stats"
    stand_in = types.ModuleType(STATS, "filterpy.stats, imported when first used")
    stand_in.__path__ = [str(folder)]
    stand_in.__file__ = str(folder / "__init__.py")      # where the real one will come from

    def real() -> types.ModuleType:
        module = sys.modules.get(STATS)
        if module is not None and module is not stand_in:
            return module
        spec = importlib.util.spec_from_file_location(
            STATS, folder / "__init__.py", submodule_search_locations=[str(folder)])
        module = importlib.util.module_from_spec(spec)
        sys.modules[STATS] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            sys.modules[STATS] = stand_in
            raise
        parent = sys.modules.get("filterpy")
        if parent is not None:
            parent.stats = module
        return module

    def logpdf(*args, **kwargs):
        return real().logpdf(*args, **kwargs)

    def attribute(name: str):
        # A module's own dunders are asked for by whatever walks sys.modules (hypothesis
        # looks at every module's __file__ for constants, in every test worker): not a use.
        if name.startswith("__") and name.endswith("__") and name != "__all__":
            raise AttributeError(name)
        return getattr(real(), name)

    stand_in.logpdf = logpdf
    stand_in.__getattr__ = attribute
    sys.modules[STATS] = stand_in


_stand_in_for_filterpy_stats()

from filterpy.kalman import IMMEstimator, KalmanFilter  # noqa: E402  (after the stand-in)
import numpy as np  # noqa: E402
from numpy import dot  # noqa: E402

__all__ = ["IMMEstimator", "KalmanFilter", "LeanKalmanFilter", "predict_all", "update_all"]


class LeanKalmanFilter(KalmanFilter):
    """filterpy's KalmanFilter with the same arithmetic in `predict` and `update`, but without
    the copies it keeps for inspection (x_prior, P_prior, z, x_post, P_post) and the
    likelihood resets, which the tracker never reads: a third of the cost of a filter step
    on a 4-state filter, for every track on every tick. Only the call forms the tracker uses
    are taken: `predict(F=..., Q=...)` and `update(z, R=..., H=...)` with arrays."""

    def predict(self, u=None, B=None, F=None, Q=None):
        if u is not None or B is not None or F is None or not hasattr(Q, "shape"):
            return super().predict(u, B, F, Q)
        self.x = dot(F, self.x)
        P = dot(dot(F, self.P), F.T)
        # times the fading factor unless it is 1 (a product by 1.0 is the same float)
        self.P = (P if self._alpha_sq == 1.0 else self._alpha_sq * P) + Q

    def update(self, z, R=None, H=None):
        if z is None or R is None or H is None or not hasattr(R, "shape"):
            return super().update(z, R, H)
        self.y = z - dot(H, self.x)
        PHT = dot(self.P, H.T)
        self.S = dot(H, PHT) + R
        self.SI = self.inv(self.S)
        self.K = dot(PHT, self.SI)
        self.x = self.x + dot(self.K, self.y)
        I_KH = self._I - dot(self.K, H)
        self.P = dot(dot(I_KH, self.P), I_KH.T) + dot(dot(self.K, R), self.K.T)


def predict_all(filters: list[LeanKalmanFilter], F, Q) -> None:
    """`predict(F=F, Q=Q)` of every filter (fading factor 1), as one product per step for the
    stack: np.matmul over a stack of matrices makes the same BLAS product for each matrix as
    np.dot makes for it alone, so every filter gets the same floats, for a fraction of the
    calls with a crowd of tracks."""
    if any(kf._alpha_sq != 1.0 for kf in filters):
        for kf in filters:
            kf.predict(F=F, Q=Q)
        return
    xs = np.matmul(F, np.array([kf.x for kf in filters]))
    ps = np.matmul(np.matmul(F, np.array([kf.P for kf in filters])), F.T)
    ps += Q
    for kf, x, p in zip(filters, xs, ps):
        kf.x, kf.P = x, p


def update_all(filters: list[LeanKalmanFilter], z: np.ndarray, R: np.ndarray, H: np.ndarray,
               inverse) -> None:
    """`filters[i].update(z[i], R=R[i], H=H)` of every filter (z (n, 2, 1), R (n, 2, 2)),
    stacked as `predict_all`; `inverse` inverts a stack of innovation covariances with the
    same floats as each filter's `inv`."""
    xs = np.array([kf.x for kf in filters])
    ps = np.array([kf.P for kf in filters])
    ys = z - np.matmul(H, xs)
    pht = np.matmul(ps, H.T)
    ss = np.matmul(H, pht) + R
    sis = inverse(ss)
    ks = np.matmul(pht, sis)
    xs = xs + np.matmul(ks, ys)
    i_kh = filters[0]._I - np.matmul(ks, H)
    ps = (np.matmul(np.matmul(i_kh, ps), np.swapaxes(i_kh, 1, 2))
          + np.matmul(np.matmul(ks, R), np.swapaxes(ks, 1, 2)))
    for kf, x, p, y, s, si, k in zip(filters, xs, ps, ys, ss, sis, ks):
        kf.x, kf.P, kf.y, kf.S, kf.SI, kf.K = x, p, y, s, si, k
