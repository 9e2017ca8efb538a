"""The receptionist, end to end on HOROS and PERSES: the same files, the same states."""
from __future__ import annotations

import sqlite3

import pytest

from applications.cli import main
from applications.trace import read_trace

EXPECTED = {
    "visitor": (["Wait", "Greet", "AskOffice", "Directions", "Goodbye", "Wait"], [("office", "N2")]),
    "unsure": (["Wait", "Greet", "AskOffice", "Reception", "Goodbye", "Wait"],
               [("office", "unknown")]),
    "walks_away": (["Wait", "Greet", "AskOffice", "Goodbye", "Wait"], []),
    "nobody": (["Wait"], []),
}


def run(tmp_path, scenario: str, robot: str):
    trace, data = tmp_path / "trace.jsonl", tmp_path / "data"
    code = main(["run", "receptionist", "--robot", robot, "--scenario", scenario, "--fast",
                 "--trace", str(trace), "--data", str(data), "--quiet"])
    with sqlite3.connect(data / "receptionist.sqlite") as db:
        answers = [tuple(r) for r in db.execute("SELECT question, answer FROM answers ORDER BY id")]
    return code, read_trace(trace), answers


@pytest.mark.parametrize("robot", ["horos", "perses"])
@pytest.mark.parametrize("scenario", sorted(EXPECTED))
def test_states_and_answers_on_both_robots(tmp_path, scenario, robot):
    code, trace, answers = run(tmp_path, scenario, robot)
    assert code == 0
    assert [e["to"] for e in trace if e["kind"] == "transition"] == EXPECTED[scenario][0]
    assert answers == EXPECTED[scenario][1]


def test_directions_come_from_the_database_for_the_chosen_office(tmp_path):
    _, trace, _ = run(tmp_path, "visitor", "horos")
    says = [e["text"] for e in trace if e["kind"] == "say"]
    assert any(text.startswith("Professor Gross is in room N2") for text in says)
    assert says[-1] == "Goodbye, and have a nice visit!"
    ask = next(e for e in trace if e["kind"] == "ask")
    assert ask["buttons"] == ["Dr. Weber (N1)", "Prof. Gross (N2)", "Ms. Klein (N3)",
                              "The laboratory (S4)", "I don't know"]


def test_a_timeout_transition_says_which_part_of_the_or_held(tmp_path):
    _, trace, _ = run(tmp_path, "walks_away", "horos")
    leave = next(e for e in trace if e["kind"] == "transition" and e["from"] == "AskOffice")
    assert leave["because"] == "not user.present"
