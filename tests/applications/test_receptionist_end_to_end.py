"""The receptionist, end to end on HOROS and PERSES: the same files, the same states."""
from __future__ import annotations

import pytest

EXPECTED = {
    "visitor": (["Wait", "Greet", "AskOffice", "Directions", "Goodbye", "Wait"], [("office", "N2")]),
    "unsure": (["Wait", "Greet", "AskOffice", "Reception", "Goodbye", "Wait"],
               [("office", "unknown")]),
    "walks_away": (["Wait", "Greet", "AskOffice", "Goodbye", "Wait"], []),
    "nobody": (["Wait"], []),
}


def run(app_runs, scenario: str, robot: str):
    done = app_runs.run("receptionist", robot, scenario)
    return done.code, done.trace, done.rows("receptionist",
                                            "SELECT question, answer FROM answers ORDER BY id")


@pytest.mark.parametrize("robot", ["horos", "perses"])
@pytest.mark.parametrize("scenario", sorted(EXPECTED))
def test_states_and_answers_on_both_robots(app_runs, scenario, robot):
    code, trace, answers = run(app_runs, scenario, robot)
    assert code == 0
    assert [e["to"] for e in trace if e["kind"] == "transition"] == EXPECTED[scenario][0]
    assert answers == EXPECTED[scenario][1]


def test_directions_come_from_the_database_for_the_chosen_office(app_runs):
    _, trace, _ = run(app_runs, "visitor", "horos")
    says = [e["text"] for e in trace if e["kind"] == "say"]
    assert any(text.startswith("Professor Gross is in room N2") for text in says)
    assert says[-1] == "Goodbye, and have a nice visit!"
    ask = next(e for e in trace if e["kind"] == "ask")
    assert ask["buttons"] == ["Dr. Weber (N1)", "Prof. Gross (N2)", "Ms. Klein (N3)",
                              "The laboratory (S4)", "I don't know"]


def test_a_timeout_transition_says_which_part_of_the_or_held(app_runs):
    _, trace, _ = run(app_runs, "walks_away", "horos")
    leave = next(e for e in trace if e["kind"] == "transition" and e["from"] == "AskOffice")
    assert leave["because"] == "not user.present"
