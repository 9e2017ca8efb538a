"""Tests of the scripts under benchmarks/ (not a package: each is loaded from its file)."""
from __future__ import annotations

import importlib.util
import sys
from contextlib import contextmanager
from pathlib import Path

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


@contextmanager
def benchmark_script(relative: str, name: str):
    """The script benchmarks/`relative` loaded as module `name`, registered in sys.modules
    while in use (its dataclasses look their module up there) and removed after."""
    spec = importlib.util.spec_from_file_location(name, BENCHMARKS / relative)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        sys.modules.pop(name, None)
