"""benchmarks/standing_apart.py: counts the runs in which the tracker splits a standing person."""
from __future__ import annotations

import pytest

from skills.people import PeopleTracker, TrackerParams
from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def standing_apart():
    with benchmark_script("standing_apart.py", "standing_apart") as module:
        yield module


def test_a_run_that_splits_a_person_is_counted_and_one_that_does_not_is_not(standing_apart,
                                                                            monkeypatch):
    assert not standing_apart.splits(1, 1567)
    # the tracker without the leftover pairing splits that person (docs/tracking.md)
    monkeypatch.setattr(standing_apart, "PeopleTracker",
                        lambda: PeopleTracker(TrackerParams(leftover_reach=0.0)))
    assert standing_apart.splits(1, 1567)
    assert not standing_apart.splits(2, 1567)


def test_the_command_prints_how_many_runs_split(standing_apart, monkeypatch, capsys):
    monkeypatch.setattr("sys.argv", ["standing_apart.py", "--first", "1567", "--seeds", "1"])
    monkeypatch.setattr(standing_apart, "PeopleTracker",
                        lambda: PeopleTracker(TrackerParams(leftover_reach=0.0)))
    standing_apart.main()
    out = capsys.readouterr().out
    assert "1 of 8 runs split" in out and "(1, 1567)" in out
