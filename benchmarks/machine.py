"""Which of numpy's SIMD kernels this machine runs, in one line for a benchmark's header.

numpy picks its float64 `exp`, `sin`, `cos`, `log` and `arctan2` kernels by the CPU at run time
(X86_V4 = AVX-512, X86_V3 = AVX2, ...), and the kernels differ in the last bit. The simulated
people, the laser's rays and localization go through them, so a crowd (chaotic) or a long run
diverges: a world digest, or a crowded family's per-seed line, is exact only between machines
whose line here is the same. Quiet runs mostly agree to the printed digit all the same.
"""
from __future__ import annotations

import numpy as np

FUNCTIONS = ("exp", "sin", "cos", "log", "arctan2")


def numpy_kernels() -> str:
    """'numpy 2.4.6, float64 kernels: exp X86_V3, ...' (numpy >= 2.0 can say; older cannot)."""
    try:
        from numpy.lib.introspect import opt_func_info
    except ImportError:
        return f"numpy {np.__version__} (it cannot say which SIMD kernels it runs)"
    parts = []
    for name in FUNCTIONS:
        found = opt_func_info(func_name=f"^{name}$").get(name, {})
        kernel = next((v["current"] for sig, v in found.items() if set(sig) == {"d"}), "?")
        parts.append(f"{name} {kernel.split('(')[-1].rstrip(')')}")
    return f"numpy {np.__version__}, float64 kernels: {', '.join(parts)}"


if __name__ == "__main__":
    print(numpy_kernels())
