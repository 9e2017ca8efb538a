"""benchmarks/suite_cpu.py: its plugin records one line per test in a real pytest run, and its
report adds them up per file and names the share of the shared whole-application runs."""
from __future__ import annotations

import os
import subprocess
import sys

import pytest

from tests.benchmarks import BENCHMARKS, benchmark_script


@pytest.fixture(scope="module")
def suite_cpu():
    with benchmark_script("suite_cpu.py", "suite_cpu") as module:
        yield module


def test_the_plugin_writes_one_line_per_test_with_its_cpu(suite_cpu, tmp_path):
    tests = tmp_path / "test_sample.py"
    tests.write_text("def test_busy():\n    sum(i * i for i in range(300_000))\n\n"
                     "def test_idle():\n    pass\n")
    out = tmp_path / "out"
    out.mkdir()
    env = dict({k: v for k, v in os.environ.items() if not k.startswith("PYTEST_XDIST")},
               **{suite_cpu.OUT_VARIABLE: str(out)},
               PYTHONPATH=os.pathsep.join([str(BENCHMARKS), os.environ.get("PYTHONPATH", "")]))
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           "-p", "suite_cpu", "-p", "no:xdist", str(tests)],
                          cwd=tmp_path, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    rows = {row[0].split("::")[-1]: row for row in suite_cpu.read_rows(out)}
    assert set(rows) == {"test_busy", "test_idle"}
    assert rows["test_busy"][1] > rows["test_idle"][1] >= 0.0
    assert all(row[2] == 0.0 and row[3] >= 0.0 for row in rows.values())
    assert rows["test_busy"][4] <= rows["test_idle"][4]          # began: run in file order
    assert rows["test_busy"][5] == "-"                              # no xdist worker


def test_the_report_adds_up_per_file_and_names_the_shared_runs(suite_cpu, capsys):
    rows = [("tests/applications/test_bundled_states.py::test_a", 6.0, 0.0, 7.0, 100.0),
            ("tests/applications/test_bundled_states.py::test_b", 2.0, 0.0, 2.5, 100.0),
            ("tests/test_docs.py::test_c", 0.5, 1.5, 3.0, 102.5)]
    suite_cpu.report(rows, top=5, wall=10.0)
    out = capsys.readouterr().out.splitlines()
    assert out[0] == ("3 tests, 10 CPU-s (8 in the workers, 2 in processes they waited for), "
                      "10 s wall")
    assert out[1] == "files reading the shared whole-application runs: 8 CPU-s (80 %)"
    assert out[3].split() == ["8.0", "80.0%", "8.0", "0.0", "2",
                              "tests/applications/test_bundled_states.py"]
    assert out[4].split() == ["2.0", "20.0%", "0.5", "1.5", "1", "tests/test_docs.py"]


def test_the_report_names_the_waiting_tests_and_the_tail(suite_cpu, capsys):
    # worker gw0 runs a (100-107); gw1 runs b (100-102.5) then c (102.5-105.5)
    rows = [("tests/test_x.py::test_a", 6.0, 0.0, 7.0, 100.0, "gw0"),
            ("tests/test_x.py::test_b", 2.0, 0.0, 2.5, 100.0, "gw1"),
            ("tests/test_y.py::test_c", 0.5, 0.5, 3.0, 102.5, "gw1")]
    suite_cpu.report(rows, top=2, wall=10.0)
    out = capsys.readouterr().out.splitlines()
    waiting = out[out.index(next(l for l in out if l.startswith("tests waiting"))) + 2:][:2]
    assert [line.split() for line in waiting] == [["2.0", "3.0", "1.0", "tests/test_y.py::test_c"],
                                                   ["1.0", "7.0", "6.0", "tests/test_x.py::test_a"]]
    assert out[-1] == ("wall clock: 10 s; 3 s outside the tests (start-up, collection, the end); "
                       "the 2 workers ran out of tests 6 s to 7 s after the first began")
