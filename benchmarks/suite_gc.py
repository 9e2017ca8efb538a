"""What a full cyclic collection costs in a test worker once the suite is collected, and after
tests/conftest.py has frozen what the tests imported (gc.freeze): the pause every thread of a
worker stands still for, which a real-time test's 0.3 s device time-out must not see.

    python benchmarks/suite_gc.py [pytest arguments, e.g. tests/faults]

It collects the tests in this process (nothing runs) and times `gc.collect()` three times at
each point; the least of the three is printed.
"""
from __future__ import annotations

import gc
import sys
import time

import pytest


def full_collection_ms() -> float:
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        gc.collect()
        best = min(best, time.perf_counter() - start)
    return best * 1000.0


class Probe:
    """Times a full collection when every test module is imported, and again once the suite's
    own collection hook has frozen them."""

    def __init__(self) -> None:
        self.lines: list[str] = []

    def pytest_collection_modifyitems(self, items) -> None:
        self.lines.append(f"collected {len(items)} tests: {len(gc.get_objects())} objects the "
                          f"collector walks, a full collection {full_collection_ms():.0f} ms")

    @pytest.hookimpl(tryfirst=True)
    def pytest_runtestloop(self, session) -> None:
        self.lines.append(f"after the suite's freeze: {gc.get_freeze_count()} objects frozen, "
                          f"{len(gc.get_objects())} walked, a full collection "
                          f"{full_collection_ms():.0f} ms")


def main(arguments: list[str]) -> int:
    probe = Probe()
    code = pytest.main(["--collect-only", "-q", "-p", "no:cacheprovider", *arguments],
                       plugins=[probe])
    print("\n".join(probe.lines))
    return int(code)


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
