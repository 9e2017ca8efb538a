"""The learner (issue 27, point 2): the bandits, the statistics in SQLite through a kill -9,
settings (freeze, minimum share, reset) and `interbot learn`."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from applications.learning import bandit
from applications.learning.store import Episode, LearningStore


@pytest.mark.parametrize("method", bandit.METHODS)
def test_each_bandit_ends_up_choosing_the_best_of_three(method):
    truth = np.array([0.2, 0.7, 0.4])
    world, rng = np.random.default_rng(1), np.random.default_rng(2)
    s, n = np.zeros(3), np.zeros(3)
    late = []
    for episode in range(600):
        arm = bandit.choose(s, n, rng, method)
        n[arm] += 1
        s[arm] += world.random() < truth[arm]
        if episode >= 400:
            late.append(arm)
    assert np.mean(np.array(late) == 1) > 0.8, (method, n)


def test_frozen_exploits_and_a_minimum_share_starves_no_one():
    rng = np.random.default_rng(0)
    assert bandit.choose([1, 8], [10, 10], rng, frozen=True) == 1
    assert all(bandit.choose([1, 8], [10, 10], rng, frozen=True) == 1 for _ in range(50))
    # arm 0 has 2 of 102 trials (< 5 %): it is tried next, even when frozen
    assert bandit.choose([0, 80], [2, 100], rng, frozen=True, min_share=0.05) == 0
    assert bandit.choose([0, 80], [6, 100], rng, frozen=True, min_share=0.05) == 1
    with pytest.raises(ValueError, match="known: thompson, ucb"):
        bandit.choose([0], [0], rng, "greedy")


def test_intervals_narrow_with_trials():
    low, high = bandit.interval(0, 0)
    assert (round(low, 3), round(high, 3)) == (0.025, 0.975)
    low, high = bandit.interval(70, 100)
    assert 0.6 < low < 0.7 < high < 0.8


def test_settings_and_reset(tmp_path):
    store = LearningStore(tmp_path / "a.sqlite", "survey", "horos")
    store.record(Episode("attract", "", "call", "learn", True, 3.0, 40.0))
    store.record(Episode("attract", "x", "face", "learn", False, 15.0, 90.0))
    assert store.counts("attract") == {"call": (1, 1), "face": (0, 1)}
    assert store.counts("attract", "x") == {"face": (0, 1)}
    other = LearningStore(tmp_path / "a.sqlite", "survey", "perses")   # per robot
    assert other.counts("attract") == {}
    store.set("attract", frozen=True)
    store.set("attract", min_share=0.1)
    assert (store.settings("attract").frozen, store.settings("attract").min_share) == (True, 0.1)
    assert store.reset("attract") == 2 and store.counts("attract") == {}


WRITER = textwrap.dedent("""
    import sys
    from applications.learning.store import Episode, LearningStore
    store = LearningStore(sys.argv[1], "survey", "horos")
    i = 0
    while True:
        store.record(Episode("attract", "", "call" if i % 3 else "face", "learn", i % 2 == 0,
                             1.0, float(i)))
        i += 1
        print(i, flush=True)
""")


def test_the_statistics_survive_a_kill_9_mid_writing(tmp_path):
    path = tmp_path / "survey.sqlite"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    writer = subprocess.Popen([sys.executable, "-c", WRITER, str(path)], stdout=subprocess.PIPE,
                              text=True, env=env)
    try:
        reported = 0
        deadline = time.monotonic() + 60
        while reported < 30 and time.monotonic() < deadline:
            reported = int(writer.stdout.readline() or 0)
        writer.send_signal(signal.SIGKILL)
        writer.wait(10)
        # the writer may have written (and said so) a few more before the kill landed: the
        # last line it got out is the last episode it reported as written
        reported = max([reported, *(int(line) for line in writer.stdout.read().split())])
    finally:
        if writer.poll() is None:
            writer.kill()
    assert reported >= 30
    store = LearningStore(path, "survey", "horos")
    assert store.db.execute("PRAGMA integrity_check").fetchone() == ("ok",)
    counts = store.counts("attract")
    trials = sum(n for _, n in counts.values())
    # every episode the writer reported as written is there (and at most the one in flight more)
    assert reported <= trials <= reported + 1
    history = store.history("attract")
    assert [a for _, a, _ in history[:6]] == ["face", "call", "call", "face", "call", "call"]
    assert [ok for _, _, ok in history[:4]] == [True, False, True, False]


@pytest.mark.parametrize("method", bandit.METHODS)
def test_a_contextual_choice_point_learns_the_best_alternative_per_context(tmp_path, method):
    """People alone come when looked at, groups when called: the chooser, writing to the
    store as runs do, learns one answer per value of people.count."""
    from applications.appfolder import load_folder
    from applications.learning.chooser import Chooser, LearnerOptions
    from tests.applications.learning_app import survey_with_choice

    points = load_folder(survey_with_choice(tmp_path / "app", context="people.count")).dialog.choices
    store = LearningStore(tmp_path / "survey.sqlite", "survey", "horos")
    truth = {1: {"face": 0.8, "call": 0.2}, 2: {"face": 0.2, "call": 0.8}}
    world = np.random.default_rng(5)
    chooser = Chooser(points, store, LearnerOptions(method=method, seed=1))
    t, late = 0.0, {1: [], 2: []}
    for episode in range(400):
        count = 1 if world.random() < 0.6 else 2
        picked = chooser.pick("CreateAttention", {"people.count": count}, t)
        came = world.random() < truth[count][picked.id]
        chooser.watch("Interaction" if came else "CreateAttention", {}, t + 2.0)
        chooser.watch("Wait", {}, t + 20.0)
        if episode >= 250:
            late[count].append(picked.id)
        t += 30.0
    assert late[1].count("face") > 0.8 * len(late[1]), late[1]
    assert late[2].count("call") > 0.8 * len(late[2]), late[2]
    assert sum(n for _, n in store.counts("attract").values()) == 400
    assert set(store.contexts("attract")) == {"people.count=1", "people.count=2"}


def _shifting_world(tmp_path, name, window):
    """400 episodes where 'face' works (80 % / 20 %), then 400 where 'call' does: the share
    of 'call' among the last 200 choices."""
    from applications.appfolder import load_folder
    from applications.learning.chooser import Chooser, LearnerOptions
    from tests.applications.learning_app import survey_with_choice

    points = load_folder(survey_with_choice(tmp_path / name)).dialog.choices
    store = LearningStore(tmp_path / f"{name}.sqlite", "survey", "horos")
    chooser = Chooser(points, store, LearnerOptions(seed=3, window=window))
    world, chosen, t = np.random.default_rng(4), [], 0.0
    for episode in range(800):
        best = "face" if episode < 400 else "call"
        picked = chooser.pick("CreateAttention", {}, t)
        came = world.random() < (0.8 if picked.id == best else 0.2)
        chooser.watch("Interaction" if came else "CreateAttention", {}, t + 2.0)
        chooser.watch("Wait", {}, t + 20.0)
        chosen.append(picked.id)
        t += 30.0
    assert chosen[300:400].count("face") > 80
    return chosen[600:].count("call") / 200


def test_a_window_lets_the_learner_follow_a_world_that_changes(tmp_path):
    windowed = _shifting_world(tmp_path, "windowed", 100)
    assert windowed > 0.8
    store = LearningStore(tmp_path / "s.sqlite", "survey", "horos")
    for i in range(5):
        store.record(Episode("attract", "", "face" if i < 3 else "call", "learn", True, 1.0, i))
    assert store.counts("attract", "", window=2) == {"call": (2, 2)}
    store.set("attract", window=2)
    assert store.settings("attract").window == 2
