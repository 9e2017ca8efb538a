"""The office guide, end to end on HOROS and PERSES: the same files, the same states, the same
log of guide runs, in every bundled scenario."""
from __future__ import annotations

import pytest

ASK = ["Wait", "Attract", "AskWhat"]
HOME = ["GoHome", "Wait"]
EXPECTED = {     # states, answers, guide runs (place, outcome)
    "follows": (ASK + ["AskRoom", "GuideToRoom", "Goodbye"] + HOME,
                [("what", "room"), ("room", "N2")], [("room_n2", "arrived")]),
    "stop_halfway": (ASK + ["AskPerson", "Whereabouts", "GuideToPerson", "Goodbye"] + HOME,
                     [("what", "person"), ("person", "gross")], [("room_n2", "arrived")]),
    "walks_away": (ASK + ["AskRoom", "GuideToRoom", "GiveUp"] + HOME,
                   [("what", "room"), ("room", "N2")], [("room_n2", "user lost")]),
    "group_blocking": (ASK + ["AskRoom", "GuideToRoom", "Goodbye"] + HOME,
                       [("what", "room"), ("room", "N1")], [("room_n1", "arrived")]),
}
CALL = "Please follow me, I am waiting for you."
EXCUSE = "Excuse me, may I pass, please?"


def run(app_runs, scenario: str, robot: str):
    """The run shared with the portability test (tests/applications/app_runs.py)."""
    done = app_runs.run("guide", robot, scenario)
    answers = done.rows("guide", "SELECT question, answer FROM answers ORDER BY id")
    runs = done.rows("guide", "SELECT place, outcome, reason, duration FROM guide_runs ORDER BY id")
    return done.code, done.trace, answers, runs


@pytest.mark.parametrize("robot", ["horos", "perses"])
@pytest.mark.parametrize("scenario", sorted(EXPECTED))
def test_states_answers_and_guide_log_on_both_robots(app_runs, scenario, robot):
    code, trace, answers, runs = run(app_runs, scenario, robot)
    states, expected_answers, expected_runs = EXPECTED[scenario]
    assert code == 0
    assert [e["to"] for e in trace if e["kind"] == "transition"] == states
    assert answers == expected_answers
    assert [(place, outcome) for place, outcome, _, _ in runs] == expected_runs
    assert all(duration > 5.0 for *_, duration in runs)
    says = [e["text"] for e in trace if e["kind"] == "say"]
    realizations = {e["realization"] for e in trace
                    if e["kind"] == "behavior" and e["name"] == "GuidePerson"}
    assert realizations == ({"head"} if robot == "horos" else {"body"})
    if scenario == "stop_halfway":
        assert CALL in says                              # stopped and asked to follow
        assert any(s.startswith("Professor Gross has his office in room N2") for s in says)
    if scenario == "walks_away":
        assert CALL in says
        assert runs[0][2].startswith("the user did not follow")
        assert "I am sorry, I lost you. I am going back to the entrance." in says
    if scenario == "group_blocking":
        assert EXCUSE in says
    if scenario == "follows":
        assert CALL not in says and EXCUSE not in says
        assert "Here we are: this is room N2." in says
