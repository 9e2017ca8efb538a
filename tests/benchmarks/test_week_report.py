"""The simulated week's report (benchmarks/campaigns/week/report.py, issue 27 point 5): the oracle
is the best alternative per context the learner sees, valued at the true rates estimated from
every strategy's episodes; first and random are valued alike; the regret and the recovery after
the shift are counted in episodes."""
from __future__ import annotations

import sqlite3

import pytest

from applications.campaign.results import SCHEMA
from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def report():
    with benchmark_script("campaigns/week/report.py", "week_report") as module:
        yield module


def episodes(session, context, alternative, successes, failures):
    return ([(session, context, alternative, True)] * successes
            + [(session, context, alternative, False)] * failures)


# Before the shift (sessions 0-1): people alone (3/4 of the episodes) come when looked at,
# in people.count=2 calling works better; after it (session 2) calling is best everywhere.
WORLD = {("random", 0, 2): (episodes(0, "people.count=1", "look", 78, 20)
                            + episodes(0, "people.count=1", "call", 18, 80)
                            + episodes(1, "people.count=2", "look", 8, 24)
                            + episodes(1, "people.count=2", "call", 23, 9)
                            + episodes(2, "people.count=1", "look", 18, 80)
                            + episodes(2, "people.count=1", "call", 78, 20))}


def test_the_oracle_takes_the_best_alternative_per_context_at_the_true_rates(report):
    before, after = report.Truth(WORLD, False), report.Truth(WORLD, True)
    assert before.best("people.count=1") == "look" and before.best("people.count=2") == "call"
    assert after.best("people.count=1") == "call"
    oracle, error = before.value(before.oracle)
    share = 196 / 260
    assert oracle == pytest.approx(share * 79 / 100 + (1 - share) * 24 / 34)
    assert 0 < error < 0.05
    first = before.value(before.first)[0]
    assert first == pytest.approx(share * 79 / 100 + (1 - share) * 9 / 34)
    assert before.value(before.random)[0] == pytest.approx(
        share * (79 + 19) / 200 + (1 - share) * (9 + 24) / 68)
    assert oracle > first > before.value(before.random)[0]


def test_regret_and_recovery_are_counted_per_episode_in_its_context(report):
    truths = report.Truth(WORLD, False), report.Truth(WORLD, True)
    learner = [(0, "people.count=1", "look", True), (1, "people.count=2", "look", False)]
    regret = report.regret(learner, 2, truths, "oracle")
    assert regret[0] == pytest.approx(0.0)
    assert regret[1] == pytest.approx(24 / 34 - 9 / 34)
    assert report.on_contexts(learner, truths[0], "oracle") == pytest.approx((79 / 100 + 24 / 34) / 2)
    assert report.on_contexts(learner, truths[0], "first") == pytest.approx((79 / 100 + 9 / 34) / 2)
    after = [(2, "people.count=1", "look", False)] * 30 + [(2, "people.count=1", "call", True)] * 120
    lines = report.recovery(after, *truths)
    assert lines[0].startswith("its choice in people.count=1") and lines[0].endswith(
        "after 41 episodes")
    assert "(expected) within 10 % of the oracle after 117 episodes" in lines[1]


def test_the_report_reads_the_campaigns_results_folders(report, tmp_path):
    (tmp_path / "learn").mkdir()
    db = sqlite3.connect(tmp_path / "learn" / "results.sqlite")
    db.executescript(SCHEMA)
    group = "app=app,robot=-,map=-,scenario=visitors,choose=learn,learner=thompson,freeze=0," \
            "window=200,shift=shifted@1"
    for session, alternative in ((0, "look"), (1, "call")):
        key = f"{group},seed=0,session={session}"
        db.execute("INSERT INTO runs VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)",
                   (key, group, "app", None, None, "visitors", 0, "learn", "thompson", 0, 0,
                    600.0, 30.0, 1, 1, 0, 0, "", "", 0.0, session, 15.0, 29.0))
        db.execute("INSERT INTO episodes VALUES (?,?,?,?,?,?,?,?)",
                   (key, 0, "attract", "people.count=1", alternative, 1, 3.0, 10.0))
    db.commit()
    db.close()
    found = report.chains(tmp_path)
    assert found == {("learn", 0, 1): [(0, "people.count=1", "look", True),
                                       (1, "people.count=1", "call", True)]}
