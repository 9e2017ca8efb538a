"""The benchmarks' header line naming numpy's SIMD kernels (benchmarks/machine.py): world
digests and crowded per-seed lines are exact only between machines whose line is the same."""
from __future__ import annotations

import builtins

import numpy as np
from numpy.lib.introspect import opt_func_info

from tests.benchmarks import benchmark_script


def test_the_line_names_numpys_version_and_each_kernel_it_runs():
    with benchmark_script("machine.py", "machine") as machine:
        line = machine.numpy_kernels()
    assert line.startswith(f"numpy {np.__version__}, float64 kernels: ")
    named = dict(part.split(" ") for part in line.split(": ", 1)[1].split(", "))
    assert list(named) == list(machine.FUNCTIONS)
    for name, kernel in named.items():       # what numpy itself says it dispatched
        signature = "ddd" if name == "arctan2" else "dd"
        assert kernel in opt_func_info(func_name=f"^{name}$")[name][signature]["current"]


def test_a_numpy_that_cannot_say_is_named_so(monkeypatch):
    real_import = builtins.__import__

    def without_introspect(name, *args, **kwargs):
        if name == "numpy.lib.introspect":
            raise ImportError(name)
        return real_import(name, *args, **kwargs)
    monkeypatch.setattr(builtins, "__import__", without_introspect)
    with benchmark_script("machine.py", "machine") as machine:
        assert machine.numpy_kernels() == (f"numpy {np.__version__} (it cannot say which SIMD "
                                           f"kernels it runs)")
