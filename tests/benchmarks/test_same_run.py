"""benchmarks/same_run.py: two runs of one tree are the same once wall-clock fields, pty names
and clock reads are left out; a real difference is named by where it first occurs."""
from __future__ import annotations

import pytest

from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def same_run():
    with benchmark_script("same_run.py", "same_run") as module:
        yield module


def tick(x: float, elapsed: float, pts: str, clock: float) -> dict:
    return {"pose": [x, 0.0], "elapsed": elapsed, "link": f"{pts} up",
            "reads": [["now", clock], ["sip", 1]]}


def test_what_varies_between_two_runs_of_one_tree_is_left_out(same_run):
    old = [tick(0.0, 0.01, "/dev/pts/3", 1.0), tick(0.1, 0.02, "/dev/pts/3", 1.1)]
    new = [tick(0.0, 0.05, "/dev/pts/7", 1.3), tick(0.1, 0.09, "/dev/pts/7", 1.2)]
    assert same_run.compare(old, new) is None


def test_a_difference_is_named_where_it_first_occurs(same_run):
    old = [tick(0.0, 0.0, "p", 0.0), tick(0.1, 0.0, "p", 0.0), tick(0.2, 0.0, "p", 0.0)]
    new = [tick(0.0, 0.0, "p", 0.0), tick(0.1000001, 0.0, "p", 0.0), tick(0.3, 0.0, "p", 0.0)]
    assert same_run.compare(old, new).startswith("tick 1.pose[0]: 0.1 != 0.1000001")
    assert same_run.compare(old, old[:2]) == "ticks 3 != 2"
    assert same_run.compare([{"a": 1}], [{"b": 1}]) == "tick 0.a: only in old"
    assert same_run.compare([], []) == "no ticks recorded (old 0, new 0)"    # nothing compared


def test_a_tree_against_itself_is_the_same(same_run, capsys):
    root = same_run.ROOT
    assert same_run.main([str(root), str(root), "receptionist/horos/nobody"]) == 0
    out = capsys.readouterr().out
    assert "receptionist/horos/nobody" in out and out.rstrip().endswith("SAME")
