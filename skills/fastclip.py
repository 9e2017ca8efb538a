"""numpy's clip ufunc itself, for hot paths.

Why: `np.clip` wraps the ufunc in a few layers of Python argument handling that cost more
than clipping the few hundred values of a tick; the ufunc gives the same values. numpy 2 keeps
it in `numpy._core.umath`, numpy 1 in `numpy.core.umath`.
"""
from __future__ import annotations

try:
    from numpy._core.umath import clip
except ImportError:     # numpy < 2
    from numpy.core.umath import clip

__all__ = ["clip"]
