"""Overlap detection: pairs that can both be true come with a witness; exclusive pairs are proved
exclusive; where the percepts give no basis to decide, the answer is 'cannot decide'."""
from __future__ import annotations

import pytest

from applications.conditions import compile_condition
from applications.conditions.analysis import (EXCLUSIVE, OVERLAP, UNDECIDED, can_be_true,
                                              can_both_be_true)
from behaviors.percepts import TIME_IN_STATE, PerceptSpec, percept_specs

OVERLAPPING = [
    ("user.distance < 0.75m", "not user.present or time_in_state > 15s"),
    ("user.present and user.distance < 0.75m", "time_in_state > 20s"),
    ("people.count >= 1", "people.count <= 1"),
    ("user.distance >= 1m", "user.distance <= 100cm"),
    ("time_in_state > 30s and people.new >= 1", "people.count > 3"),
    ("not survey.done", "not user.present"),
    ("true", "user.left"),
    ("user.distance != 0.5", "user.distance > 0.2 and user.distance < 0.8"),
]
EXCLUSIVE_PAIRS = [
    ("survey.done", "not user.present and not survey.done"),
    ("user.distance < 0.75m", "user.distance >= 75cm"),
    ("people.count >= 2", "people.count <= 1"),
    ("people.count > 1.5", "people.count < 2"),
    ("time_in_state > 1min", "time_in_state < 60s"),
    ("user.present", "not user.present"),
    ("user.distance < 0.5 and people.count > 3", "user.distance > 0.6 or people.count < 2"),
    ("survey.done == true", "survey.done == false"),
    ("false", "true"),
]


@pytest.mark.parametrize("first, second", OVERLAPPING)
def test_overlapping_pairs_come_with_a_witness_that_makes_both_true(first, second) -> None:
    a, b = compile_condition(first), compile_condition(second)
    verdict = can_both_be_true(a, b)
    assert verdict.status == OVERLAP
    values = dict(verdict.witness)
    t = values.pop("time_in_state", 0.0)
    assert a.evaluate(values, t) and b.evaluate(values, t)


@pytest.mark.parametrize("first, second", EXCLUSIVE_PAIRS)
def test_exclusive_pairs_are_proved_exclusive(first, second) -> None:
    verdict = can_both_be_true(compile_condition(first), compile_condition(second))
    assert verdict.status == EXCLUSIVE
    assert verdict.witness is None


def test_the_design_example_witness_reads_like_the_paper() -> None:
    verdict = can_both_be_true(compile_condition("user.distance < 0.75m"),
                               compile_condition("not user.present or time_in_state > 15s"))
    text = verdict.describe_witness()
    assert "user.distance = 0.4 m" in text and "time_in_state = 16 s" in text


def test_a_percept_without_a_range_cannot_be_decided() -> None:
    declarations = {**percept_specs(), "time_in_state": TIME_IN_STATE,
                    "crowd.noise": PerceptSpec("crowd.noise", "float", None, None)}
    a = compile_condition("crowd.noise > 10", declarations=declarations)
    b = compile_condition("crowd.noise < 20", declarations=declarations)
    verdict = can_both_be_true(a, b)
    assert verdict.status == UNDECIDED
    assert "crowd.noise" in verdict.reason and "no range" in verdict.reason
    c = compile_condition("crowd.noise < 5", declarations=declarations)
    assert can_both_be_true(a, c).status == EXCLUSIVE    # exclusive for every value: decidable


def test_two_percepts_compared_with_each_other_cannot_be_proved_exclusive() -> None:
    declarations = {**percept_specs(), "time_in_state": TIME_IN_STATE,
                    "people.left": PerceptSpec("people.left", "int", None, (0, 1000))}
    a = compile_condition("people.count > people.left", declarations=declarations)
    b = compile_condition("people.count < people.left", declarations=declarations)
    assert can_both_be_true(a, b).status == UNDECIDED


@pytest.mark.parametrize("text, expected", [
    ("user.distance < 0.5m and user.distance > 0.6m", EXCLUSIVE),
    ("people.count > 1000", EXCLUSIVE),               # outside the declared range 0..1000
    ("user.present and not user.present", EXCLUSIVE),
    ("false", EXCLUSIVE),
    ("user.distance < 0.5m and user.distance > 0.4m", OVERLAP),
    ("time_in_state > 30s", OVERLAP),
])
def test_conditions_that_can_never_be_true(text, expected) -> None:
    assert can_be_true(compile_condition(text)).status == expected
