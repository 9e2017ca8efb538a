"""The office survey, end to end through all four layers, on every bundled scenario.

Each run goes through the command line in --fast mode; the test reads the trace for the exact
sequence of states and the SQLite database for the answers the scripted people pressed.
"""
from __future__ import annotations

import sqlite3

import pytest

from applications.cli import main
from applications.trace import read_trace

# scenario → (states visited in order, answers stored in order as (question, answer))
EXPECTED = {
    "nobody": (["Wait"], []),
    "passerby": (["Wait", "CreateAttention", "Wait"], []),
    "complete": (["Wait", "CreateAttention", "Interaction", "Wait"],
                 [("q1", "yes"), ("q2", "3"), ("q3", "no")]),
    "callback": (["Wait", "CreateAttention", "Interaction", "CallBack", "Interaction", "Wait"],
                 [("q1", "no"), ("q2", "4"), ("q3", "yes")]),
    "leave_midway": (["Wait", "CreateAttention", "Interaction", "CallBack", "Wait"],
                     [("q1", "yes")]),
    "two_people": (["Wait", "CreateAttention", "Interaction", "Wait"],
                   [("q1", "no"), ("q2", "5"), ("q3", "yes")]),
}


def run_survey(tmp_path, scenario: str, robot: str = "horos", seed: int = 0,
               extra: tuple[str, ...] = ()) -> tuple[list[dict], list[tuple[str, str]], int]:
    tmp_path.mkdir(parents=True, exist_ok=True)         # --trace wants an existing folder
    trace = tmp_path / f"{scenario}-{robot}-{seed}.jsonl"
    data = tmp_path / f"data-{scenario}-{robot}-{seed}"
    code = main(["run", "survey", "--robot", robot, "--scenario", scenario, "--fast",
                 "--seed", str(seed), "--trace", str(trace), "--data", str(data), "--quiet",
                 *extra])
    with sqlite3.connect(data / "survey.sqlite") as db:
        answers = [tuple(row) for row in db.execute("SELECT question, answer FROM answers ORDER BY id")]
    return read_trace(trace), answers, code


def states(trace: list[dict]) -> list[str]:
    return [e["to"] for e in trace if e["kind"] == "transition"]


@pytest.mark.parametrize("scenario", sorted(EXPECTED))
def test_scenario_states_and_answers(app_runs, scenario):
    run = app_runs.run("survey", "horos", scenario)
    expected_states, expected_answers = EXPECTED[scenario]
    assert run.code == 0
    assert run.states == expected_states
    assert run.rows("survey", "SELECT question, answer FROM answers ORDER BY id") == \
        expected_answers


def test_trace_lines_carry_time_kind_and_fields(app_runs):
    trace = app_runs.run("survey", "horos", "complete").trace
    kinds = {e["kind"] for e in trace}
    assert {"transition", "behavior", "say", "ask", "answer", "skill"} <= kinds
    assert all(isinstance(e["t"], (int, float)) for e in trace)
    times = [e["t"] for e in trace]
    assert times == sorted(times)
    transition = next(e for e in trace if e["kind"] == "transition" and e["from"] == "Wait")
    assert transition["to"] == "CreateAttention" and "people.new" in transition["when"]
    ask = next(e for e in trace if e["kind"] == "ask")
    assert ask["question"] == "q1" and ask["buttons"] == ["yes", "no"]


def test_same_seed_same_trace(tmp_path):
    first, _, _ = run_survey(tmp_path / "a", "two_people", seed=7)
    second, _, _ = run_survey(tmp_path / "b", "two_people", seed=7)
    assert first == second


def test_dialog_manager_override_is_traced(app_runs):
    """The person is still far (> 2.5 m) on entering CreateAttention: AttractAttention, not FaceUser."""
    trace = app_runs.run("survey", "horos", "complete").trace
    entered = next(i for i, e in enumerate(trace)
                   if e["kind"] == "transition" and e["to"] == "CreateAttention")
    behavior = next(e for e in trace[entered:] if e["kind"] == "behavior")
    assert behavior["name"] in ("AttractAttention", "FaceUser")
    says = [e["text"] for e in trace[entered:] if e["kind"] == "say"]
    assert says, "the robot says something when it creates attention"


def test_real_time_run_keeps_the_10_hz_tick(tmp_path, capsys):
    """Without --fast the loop runs on the real clock, with the emulator on its own thread."""
    trace = tmp_path / "rt.jsonl"
    code = main(["run", "survey", "--duration", "1.5", "--scenario", "nobody",
                 "--trace", str(trace), "--data", str(tmp_path), "--quiet"])
    out = capsys.readouterr().out
    assert code == 0
    assert "in 15 ticks" in out
    assert states(read_trace(trace)) == ["Wait"]
