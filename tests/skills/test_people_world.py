"""The tracker in the simulated world, scored by benchmarks/eval_tracker.py (one seed each)."""
from __future__ import annotations

import pytest
from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def evaluation():
    with benchmark_script("eval_tracker.py", "eval_tracker") as module:
        yield module


def test_ten_people_crossing_meet_the_targets_and_the_hidden_one_keeps_the_id(evaluation):
    rows = evaluation.evaluate(["crossing_10"], evaluation.Options(), seeds=1)
    summary, (acc,) = rows["crossing_10"]
    assert summary["mota"] >= 0.90 and summary["idf1"] >= 0.85
    assert evaluation.ids_per_person(acc)["pillar"] == 1


def test_the_empty_hallway_stays_empty_even_while_the_robot_turns(evaluation):
    options = evaluation.Options(spin=0.5)
    acc = evaluation.run(evaluation.HERE / "empty_hallway.toml", "office", options)
    assert acc.mot_events.empty or (acc.mot_events.Type != "FP").all()
