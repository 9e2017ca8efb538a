"""benchmarks/suite_gc.py, and what it checks: once the tests are collected, what they imported
is frozen out of the cyclic collector's walk (tests/conftest.py), so a full collection in a
worker no longer stalls its real-time tests."""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_collected_suite_is_frozen_before_the_tests_run():
    done = subprocess.run([sys.executable, "benchmarks/suite_gc.py",
                           "tests/benchmarks/test_machine.py"],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    before = re.search(r"collected (\d+) tests: (\d+) objects the collector walks, a full "
                       r"collection (\d+) ms", done.stdout)
    after = re.search(r"after the suite's freeze: (\d+) objects frozen, (\d+) walked", done.stdout)
    assert before and after, done.stdout
    assert int(before.group(1)) == 2                        # the two tests of that file
    frozen, walked = int(after.group(1)), int(after.group(2))
    assert frozen > 10_000                                  # pytest, numpy, the test modules …
    assert walked < frozen / 100                            # … and next to nothing left to walk
