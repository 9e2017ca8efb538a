"""Campaigns (issue 27, points 4 and 6): the spec, a small campaign run locally and resumed,
the same campaign on a local Ray instance giving the same results, and the learner finding the
best alternative in a short seeded campaign."""
import sqlite3
from pathlib import Path

import pytest

from applications.campaign.command import CampaignCommand
from applications.campaign.spec import load_campaign
from applications.cli import build_parser
from applications.exceptions import ApplicationError

ATTRACT = Path(__file__).resolve().parents[2] / "benchmarks" / "campaigns" / "attract"

# Passers-by every 12-14 s who come when looked at (95 %) and almost never when called (5 %),
# then walk on at once: many short episodes.
QUICK = """
[scenario]
name = "quick"
duration = 600.0
robot = "robot_home"

[visitors]
count = 60
first = 8.0
every = [12.0, 14.0]
[visitors.people]
voice = [1, 19]
head = [19, 1]
drive = [1, 19]
patience = [0.0, 0.0]
"""


def spec(tmp_path, seeds="2", choose='["learn"]', duration=40.0, extra="") -> Path:
    (tmp_path / "quick.toml").write_text(QUICK)
    path = tmp_path / "spec.toml"
    path.write_text(f'[campaign]\nname = "t"\napp = "{ATTRACT / "app"}"\n'
                    f'scenarios = ["quick.toml"]\nseeds = {seeds}\nduration = {duration}\n'
                    f'workers = 2\n{extra}\n[learner]\nchoose = {choose}\n')
    return path


def campaign(*argv) -> int:
    args = build_parser({"campaign": CampaignCommand()}).parse_args(["campaign", *map(str, argv)])
    return args.handler.run(args)


def table(path: Path):
    db = sqlite3.connect(path)
    try:
        return (db.execute("SELECT key, exit_code, episodes, successes, surveys, answers, "
                           "robot_seconds FROM runs ORDER BY key").fetchall(),
                db.execute("SELECT * FROM episodes ORDER BY key, n").fetchall())
    finally:
        db.close()


def test_the_grid_of_a_spec(tmp_path):
    found = load_campaign(spec(tmp_path, seeds="[3, 5]", choose='["learn", "first", "random"]'))
    assert len(found.runs) == 6 and {r.seed for r in found.runs} == {3, 5}
    assert len({r.key for r in found.runs}) == 6
    argv = found.runs[0].argv(tmp_path / "r")
    assert argv[:3] == ["run", str(ATTRACT / "app"), "--fast"] and "--choose" in argv
    kept = load_campaign(spec(tmp_path, extra="record = true"))
    assert "--record" in kept.runs[0].argv(tmp_path / "r")
    windowed = spec(tmp_path)
    windowed.write_text(windowed.read_text() + "window = [0, 50]\n")
    runs = load_campaign(windowed).runs
    assert ["--window", "50"] == runs[-1].argv(tmp_path)[-2:] and len(runs) == 4
    bad = spec(tmp_path, choose='["best"]')
    with pytest.raises(ApplicationError, match=r"spec.toml: learner.choose: 'best' is not one of"):
        load_campaign(bad)
    bad.write_text(bad.read_text().replace("seeds = 2", "seeds = 0"))
    with pytest.raises(ApplicationError, match=r"campaign.seeds: = 0 must be a count"):
        load_campaign(bad)


@pytest.fixture(scope="module")
def local_results(tmp_path_factory):
    folder = tmp_path_factory.mktemp("campaign")
    path = spec(folder)
    assert campaign(path, "--out", folder / "local") == 0
    return path, folder / "local"


@pytest.mark.slow
def test_a_small_campaign_runs_locally_keeps_each_run_and_resumes(local_results, capsys):
    path, out = local_results
    runs, episodes = table(out / "results.sqlite")
    assert [r[1] for r in runs] == [0, 0] and all(r[2] >= 1 for r in runs)
    assert len(episodes) == sum(r[2] for r in runs)
    for folder in (out / "runs").iterdir():
        assert (folder / "trace.jsonl").exists() and "ran 40.0 s" in (folder / "output.txt").read_text()
    assert (out / "curves.svg").read_text().startswith("<svg")
    assert "choose=learn" in (out / "summary.txt").read_text()
    capsys.readouterr()
    assert campaign(path, "--out", out) == 0               # everything done: nothing runs
    assert "2 done before, 0 to run" in capsys.readouterr().out
    db = sqlite3.connect(out / "results.sqlite")
    with db:
        db.execute("UPDATE runs SET exit_code = 4 WHERE seed = 1")    # as if it had crashed
    db.close()
    assert campaign(path, "--out", out) == 1                # a failed run is kept, and reported
    assert "2 done before, 0 to run" in capsys.readouterr().out
    assert campaign(path, "--out", out, "--retry-failed") == 0
    assert "1 done before, 1 to run" in capsys.readouterr().out
    assert table(out / "results.sqlite") == (runs, episodes)


@pytest.mark.slow
def test_the_same_campaign_on_a_local_ray_instance_gives_the_same_results(local_results):
    path, out = local_results
    one = path.with_name("one.toml")                  # seed 1 only: Ray's start is the cost
    one.write_text(path.read_text().replace("seeds = 2", "seeds = [1]"))
    assert campaign(one, "--out", out.parent / "ray", "--ray", "local") == 0
    runs, episodes = table(out / "results.sqlite")
    on_ray = table(out.parent / "ray" / "results.sqlite")
    assert on_ray[0] == [r for r in runs if ",seed=1," in r[0]] and len(on_ray[0]) == 1
    assert on_ray[1] == [e for e in episodes if ",seed=1," in e[0]] and on_ray[1]


@pytest.mark.slow
def test_the_learner_finds_the_best_alternative_in_a_short_seeded_campaign(tmp_path):
    path = spec(tmp_path, seeds="1", choose='["learn"]', duration=360.0)
    assert campaign(path, "--out", tmp_path / "out") == 0
    db = sqlite3.connect(tmp_path / "out" / "results.sqlite")
    chosen = [a for (a,) in db.execute("SELECT alternative FROM episodes ORDER BY n")]
    assert len(chosen) >= 16, chosen
    late = chosen[len(chosen) // 2:]
    assert late.count("look") >= 0.8 * len(late), chosen


@pytest.mark.slow
def test_a_terminated_campaign_stops_its_runs_and_carries_on_where_it_stopped(tmp_path):
    import os
    import signal
    import subprocess
    import sys
    import time

    path, out = spec(tmp_path, seeds="3", duration=20.0), tmp_path / "out"
    path.write_text(path.read_text().replace("workers = 2", "workers = 1"))
    command = [sys.executable, "-m", "applications.cli", "campaign", str(path), "--out", str(out)]
    campaign_process = subprocess.Popen(command, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True,
                                        env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    try:
        deadline = time.monotonic() + 240
        while time.monotonic() < deadline and not (out / "results.sqlite").exists():
            time.sleep(0.2)
        while time.monotonic() < deadline and len(table(out / "results.sqlite")[0]) < 1:
            time.sleep(0.2)
        campaign_process.send_signal(signal.SIGTERM)
        _, err = campaign_process.communicate(timeout=60)
    finally:
        if campaign_process.poll() is None:
            campaign_process.kill()
    assert campaign_process.returncode == 130 and "run the same command again" in err
    still = subprocess.run(["pgrep", "-f", str(out)], capture_output=True, text=True).stdout
    assert still.strip() == ""                       # no run of it is left running
    done = len(table(out / "results.sqlite")[0])
    assert 1 <= done < 3
    assert campaign(path, "--out", out) == 0
    assert len(table(out / "results.sqlite")[0]) == 3
