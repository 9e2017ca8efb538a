"""Campaigns made cheap and long (issue 27, point 5): the worker process that runs many runs in
turn, and chains of sessions (a simulated week) whose sessions start from the statistics the
one before left, with a shift of the world from a given session on."""
import sqlite3
import threading
import time
from pathlib import Path

import pytest

from applications.campaign import engine
from applications.campaign.results import Results
from applications.campaign.spec import RunSpec, load_campaign
from applications.campaign.worker import run_job
from applications.exceptions import ApplicationError

from tests.applications.test_campaign import ATTRACT, campaign, spec, table

CHAIN = 'sessions = 3\nshift = { session = 2, scenario = "shifted.toml", app = "other" }\n'


def chained(tmp_path, extra=CHAIN, **kwargs) -> Path:
    (tmp_path / "shifted.toml").write_text("[scenario]\nname = \"shifted\"\n")
    (tmp_path / "other").mkdir(exist_ok=True)
    return spec(tmp_path, extra=extra, **kwargs)


def test_sessions_make_a_chain_per_row_and_the_shift_changes_the_world(tmp_path):
    runs = load_campaign(chained(tmp_path, seeds="2")).runs
    assert len(runs) == 6 and len({r.key for r in runs}) == 6
    assert len({r.group for r in runs}) == 1              # a chain is one row of the summary
    assert [(r.seed, r.session, r.run_seed) for r in runs[:3]] == [(0, 0, 0), (0, 1, 1), (0, 2, 2)]
    assert runs[3].run_seed == 1000 and runs[5].run_seed == 1002
    before, after = runs[1].argv(tmp_path / "r"), runs[2].argv(tmp_path / "r")
    assert before[1] == str(ATTRACT / "app") and before[before.index("--scenario") + 1].endswith(
        "quick.toml")
    assert after[1] == str(tmp_path / "other") and after[after.index("--scenario") + 1] == str(
        tmp_path / "shifted.toml")
    assert runs[2].previous == runs[1] and runs[0].previous is None
    alone = load_campaign(spec(tmp_path)).runs[0]           # no sessions: keys as before
    assert "session" not in alone.key and alone.run_seed == alone.seed


@pytest.mark.parametrize("extra, message", [
    ("sessions = 0\n", r"campaign.sessions: = 0 must be a whole number 1 \.\. 1000"),
    ("sessions = 3\nshift = { session = 3, app = \"other\" }\n",
     r"campaign.shift.session: = 3 must be a session 1 \.\. 2"),
    ("sessions = 3\nshift = { session = 1 }\n", r"campaign.shift: says nothing changes"),
    ("sessions = 3\nshift = { session = 1, when = 2 }\n", r"campaign.shift.when: unknown field"),
])
def test_a_wrong_chain_is_refused_naming_the_field(tmp_path, extra, message):
    with pytest.raises(ApplicationError, match=message):
        load_campaign(chained(tmp_path, extra=extra))


def test_a_later_session_starts_from_the_databases_the_one_before_left(tmp_path):
    first, second = load_campaign(chained(tmp_path)).runs[:2]
    runs = tmp_path / "runs"
    (runs / first.folder_name).mkdir(parents=True)
    (runs / first.folder_name / "attract.sqlite").write_bytes(b"statistics of session 0")
    (runs / first.folder_name / "trace.jsonl").write_text("not carried over")
    stale = runs / second.folder_name
    stale.mkdir()
    (stale / "attract.sqlite").write_bytes(b"an interrupted session 1")
    engine.prepare(second, stale)
    assert sorted(p.name for p in stale.iterdir()) == ["attract.sqlite"]
    assert (stale / "attract.sqlite").read_bytes() == b"statistics of session 0"


def _result(outcomes):
    return {"exit_code": 0, "robot_seconds": 10.0, "wall_seconds": 1.0, "surveys": 0,
            "answers": 0, "last_line": [""],
            "episodes": [{"point": "p", "context": "", "alternative": "a", "success": ok,
                          "after": 1.0, "t": float(n)} for n, ok in enumerate(outcomes)]}


def test_the_outcomes_of_a_chain_follow_its_sessions_in_order(tmp_path):
    runs = load_campaign(chained(tmp_path, extra=CHAIN.replace("3", "12"), seeds="2")).runs
    results = Results(tmp_path / "results.sqlite")
    for run in reversed(runs):                               # finished in any order
        results.add(run, _result([run.session % 2 == 0, run.seed == 1]), tmp_path)
    per_seed = results.outcomes(runs[0].group)
    assert per_seed[0] == [ok for s in range(12) for ok in (s % 2 == 0, False)]
    assert per_seed[1] == [ok for s in range(12) for ok in (s % 2 == 0, True)]
    assert results.groups()[0][1] == 24
    results.close()


def test_a_results_file_from_before_sessions_gets_the_session_column(tmp_path):
    old = sqlite3.connect(tmp_path / "results.sqlite")
    old.execute("CREATE TABLE runs (key TEXT PRIMARY KEY, grp TEXT NOT NULL, app TEXT NOT NULL, "
                "robot TEXT, map TEXT, scenario TEXT NOT NULL, seed INTEGER NOT NULL, choose "
                "TEXT, learner TEXT NOT NULL, freeze INTEGER NOT NULL, exit_code INTEGER NOT "
                "NULL, robot_seconds REAL NOT NULL, wall_seconds REAL NOT NULL, episodes "
                "INTEGER NOT NULL, successes INTEGER NOT NULL, surveys INTEGER NOT NULL, "
                "answers INTEGER NOT NULL, folder TEXT NOT NULL, last_line TEXT NOT NULL, "
                "finished REAL NOT NULL)")
    old.close()
    results = Results(tmp_path / "results.sqlite")
    run = load_campaign(spec(tmp_path)).runs[0]
    results.add(run, _result([True, False]), tmp_path)
    assert results.outcomes(run.group) == [[True, False]]
    results.close()


def test_each_run_keeps_its_cpu_time_and_the_summary_gives_it_per_episode(tmp_path):
    from applications.campaign.command import summary_lines
    runs = load_campaign(chained(tmp_path, seeds="1")).runs
    results = Results(tmp_path / "results.sqlite")
    results.add(runs[0], {**_result([True, False]), "cpu_seconds": 3.0, "tick_seconds": 2.5},
                tmp_path)
    results.add(runs[1], {**_result([True, True, False]), "cpu_seconds": 1.5}, tmp_path)
    results.add(runs[2], _result([True]), tmp_path)          # a run whose CPU time is unknown
    assert results.groups()[0][8:] == (4.5, 5)
    assert summary_lines(results)[1].endswith("    0.90")
    results.close()


def test_a_run_in_a_process_of_its_own_reports_its_cpu_time(tmp_path):
    import subprocess
    import sys
    busy = subprocess.Popen([sys.executable, "-c", "sum(range(3 * 10**7)); raise SystemExit(3)"])
    code, cpu = engine._wait(busy)
    assert code == 3 and busy.returncode == 3 and cpu > 0.1


def test_the_worker_runs_interbot_with_its_output_in_the_file(tmp_path):
    code = run_job(["run", "no-such-application", "--fast"], str(tmp_path / "out.txt"))
    assert code == 2
    assert "no-such-application" in (tmp_path / "out.txt").read_text()
    assert run_job(["run", "--no-such-option"], str(tmp_path / "bad.txt")) == 2
    assert "unrecognized arguments" in (tmp_path / "bad.txt").read_text() or \
        "required" in (tmp_path / "bad.txt").read_text()


@pytest.mark.slow
def test_a_worker_that_dies_mid_run_counts_it_failed_and_starts_again(tmp_path):
    import os
    import sys
    run = RunSpec(app=str(ATTRACT / "app"), robot=None, map=None,
                  scenario=str(ATTRACT / "visitors.toml"), seed=0, choose="learn",
                  learner="thompson", freeze=False, duration=3.0)
    worker = engine.Worker(os.pathsep.join(sys.path))
    try:
        long = RunSpec(**{**run.__dict__, "duration": 3600.0})
        killer = threading.Thread(target=lambda: (time.sleep(3.0), worker.process.kill()))
        killer.start()
        died = worker.run(long, tmp_path / "died")
        killer.join()
        assert died["exit_code"] == -9
        again = worker.run(run, tmp_path / "again")
        assert again["exit_code"] == 0 and again["robot_seconds"] == 3.0
        assert again["cpu_seconds"] > 0 and 0 < again["tick_seconds"] <= again["wall_seconds"]
    finally:
        worker.close()


@pytest.mark.slow
def test_a_chained_campaign_carries_the_learner_from_session_to_session(tmp_path):
    path = chained(tmp_path, seeds="1", duration=30.0,
                   extra='sessions = 2\nshift = { session = 1, scenario = "quick.toml" }\n')
    out = tmp_path / "out"
    assert campaign(path, "--out", out) == 0
    runs, episodes = table(out / "results.sqlite")
    assert [r[1] for r in runs] == [0, 0] and all(r[2] >= 1 for r in runs)
    first, second = sorted(load_campaign(path).runs, key=lambda r: r.session)

    def learned(run):
        db = sqlite3.connect(out / "runs" / run.folder_name / "attract.sqlite")
        try:
            return db.execute("SELECT * FROM learning_episodes").fetchall()
        finally:
            db.close()
    before, after = learned(first), learned(second)
    assert before and after[:len(before)] == before and len(after) > len(before)
