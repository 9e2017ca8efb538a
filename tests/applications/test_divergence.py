"""Why a replay diverged: the condition that held on one side and not on the other, with the
percept values of both sides."""
from __future__ import annotations

import shutil

import pytest

from applications.divergence import explain
from applications.graph.loader import find_application, load_application

SURVEY = find_application("survey")


@pytest.fixture(scope="module")
def survey():
    return load_application(SURVEY, robot="horos")


@pytest.fixture(scope="module")
def closer(tmp_path_factory):
    """The survey with CreateAttention -> Interaction at 0.6 m instead of 0.75 m."""
    folder = tmp_path_factory.mktemp("closer") / "survey"
    shutil.copytree(SURVEY, folder)
    graph = folder / "graph.xml"
    graph.write_text(graph.read_text().replace('when="user.distance &lt; 0.75m"',
                                               'when="user.distance &lt; 0.6m"', 1))
    return load_application(folder, robot="horos")


def tick(state: str, t: float, time_in_state: float, transition=None, **percepts) -> dict:
    return {"t": t, "state": state, "time_in_state": time_in_state, "transition": transition,
            "robot": {"percepts": {name: {"value": value, "age": 0.0, "stale": False}
                                   for name, value in percepts.items()}}}


PREVIOUS = tick("CreateAttention", 12.0, 3.0, **{"user.distance": 0.8, "user.present": True})


def test_a_changed_threshold_shows_both_conditions_and_the_value_they_read(survey, closer):
    fired = {"from": "CreateAttention", "to": "Interaction", "when": "user.distance < 0.75m"}
    recorded = tick("Interaction", 12.1, 0.0, fired, **{"user.distance": 0.7,
                                                        "user.present": True})
    replayed = tick("CreateAttention", 12.1, 3.1, **{"user.distance": 0.7,
                                                     "user.present": True})
    lines = explain(recorded, replayed, PREVIOUS, survey, closer)
    assert lines == [
        "why: in CreateAttention (after 3.1 s), each side's transitions on its own percepts:",
        "  recorded  CreateAttention -> Interaction when user.distance < 0.75m: held",
        "  replay    CreateAttention -> Interaction when user.distance < 0.6m: did not hold",
        "  percepts they read, recorded / replay:",
        "    user.distance = 0.700 / 0.700"]


def test_the_same_condition_on_different_percepts_shows_the_values_that_differ(survey):
    recorded = tick("CreateAttention", 12.1, 3.1, **{"user.distance": 0.9,
                                                     "user.present": True})
    replayed = tick("Wait", 12.1, 0.0, {"from": "CreateAttention", "to": "Wait",
                                        "when": "not user.present or time_in_state > 15s"},
                    **{"user.distance": None, "user.present": False})
    lines = explain(recorded, replayed, PREVIOUS, survey, survey)
    assert lines[1:3] == [
        "  recorded  CreateAttention -> Wait when not user.present or time_in_state > 15s: "
        "did not hold",
        "  replay    CreateAttention -> Wait when not user.present or time_in_state > 15s: held"]
    assert "    user.present = True / False" in lines


def test_without_the_recorded_application_its_recorded_condition_text_is_used(closer):
    fired = {"from": "CreateAttention", "to": "Interaction", "when": "user.distance < 0.75m"}
    recorded = tick("Interaction", 12.1, 0.0, fired, **{"user.distance": 0.7})
    replayed = tick("CreateAttention", 12.1, 3.1, **{"user.distance": 0.7})
    lines = explain(recorded, replayed, PREVIOUS, None, closer)
    assert "  recorded  CreateAttention -> Interaction when user.distance < 0.75m: held" in lines
    assert "  replay    CreateAttention -> Interaction when user.distance < 0.6m: did not hold" \
        in lines


def test_a_difference_below_the_state_graph_says_so_with_the_percepts_that_differ(survey):
    same = {"user.distance": 0.9, "user.present": True}
    assert explain(tick("CreateAttention", 12.1, 3.1, **same),
                   tick("CreateAttention", 12.1, 3.1, **same), PREVIOUS, survey, survey) == [
        "why: no transition of CreateAttention decided differently; the percepts are alike on "
        "both sides, so the difference is in the behavior or the skills below the state graph"]
    lines = explain(tick("CreateAttention", 12.1, 3.1, **same, **{"people.count": 1}),
                    tick("CreateAttention", 12.1, 3.1, **same, **{"people.count": 2}),
                    PREVIOUS, survey, survey)
    assert lines == ["why: no transition of CreateAttention decided differently; the percepts "
                     "that differ:", "    people.count = 1 / 2"]
