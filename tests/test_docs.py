"""Every example in docs/ is run: the application examples are written out and checked (and run
where they bring a scenario); the plugin package of docs/plugins.md is built, installed into a
folder of its own and used by an application; the percept list names every declared percept."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

import pytest

from behaviors.percepts import percept_specs

DOCS = Path(__file__).resolve().parent.parent / "docs"
ROOT = DOCS.parent
EXAMPLE = re.compile(r"<!-- example: (?P<name>[\w-]+) -->\s*```\w+ file=(?P<file>\S+)\n"
                     r"(?P<body>.*?)```", re.DOTALL)


def examples() -> dict[str, dict[str, str]]:
    """example name -> {file path: text}, over every page of docs/."""
    found: dict[str, dict[str, str]] = defaultdict(dict)
    for page in sorted(DOCS.glob("*.md")):
        for match in EXAMPLE.finditer(page.read_text(encoding="utf-8")):
            found[match["name"]][match["file"]] = match["body"]
    return dict(found)


def write(files: dict[str, str], folder: Path) -> None:
    for name, text in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


def cli(*args: str, env: dict | None = None, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "applications.cli", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=300, env=env)


APPS = sorted(name for name, files in examples().items() if "graph.xml" in files)


def test_the_docs_have_examples():
    assert {"greeter", "dialog-per-state", "questions", "plugin"} <= set(examples())


@pytest.mark.parametrize("name", APPS)
def test_application_examples_check_clean(tmp_path, name):
    folder = tmp_path / name
    write(examples()[name], folder)
    result = cli("check", str(folder))
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 errors, 0 warnings" in result.stdout


def test_the_kiosk_example_asks_again_and_its_visitor_answers_again(tmp_path):
    """docs/applications.md: parameters in conditions, an "another question?" loop, and a
    simulated visitor answering the same question twice."""
    folder = tmp_path / "kiosk"
    write(examples()["kiosk"], folder)
    trace = tmp_path / "run.jsonl"
    ran = cli("run", str(folder), "--fast", "--quiet", "--trace", str(trace),
              "--data", str(tmp_path / "data"))
    assert ran.returncode == 0, ran.stdout + ran.stderr
    events = [json.loads(line) for line in trace.read_text().splitlines()]
    states = [e["to"] for e in events if e["kind"] == "transition"]
    assert states == ["Wait", "Greet", "Ask", "Hours", "Again", "Ask", "Hours", "Again", "Wait"]
    answers = [(e["question"], e["answer"]) for e in events if e["kind"] == "answer"]
    assert answers == [("topic", "hours"), ("again", "yes"), ("topic", "hours"), ("again", "no")]
    greeted = next(e for e in events if e["kind"] == "transition" and e["to"] == "Ask")
    assert greeted["when"] == "user.distance < param.near"


def test_the_plugin_package_installs_and_runs_an_application(tmp_path):
    write(examples()["plugin"], tmp_path)
    site = tmp_path / "site"
    pip = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps",
                          "--no-build-isolation", "--target", str(site), str(tmp_path / "beckon")],
                         capture_output=True, text=True, timeout=300)
    assert pip.returncode == 0, pip.stderr
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}
    listed = cli("behaviors", env=env)
    assert "Beckon" in listed.stdout and "parameter every: duration" in listed.stdout
    assert "people.near" in cli("percepts", env=env).stdout
    checked = cli("check", str(tmp_path / "app"), env=env)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    trace = tmp_path / "run.jsonl"
    ran = cli("run", str(tmp_path / "app"), "--fast", "--quiet", "--trace", str(trace),
              "--data", str(tmp_path / "data"), env=env)
    assert ran.returncode == 0, ran.stdout + ran.stderr
    states = [line for line in trace.read_text().splitlines() if '"transition"' in line]
    assert any('"to": "Call"' in line for line in states)
    assert any('"from": "Call", "to": "Wait"' in line for line in states)


def test_a_plugin_that_fails_to_load_disables_only_itself(tmp_path):
    package = tmp_path / "broken"
    write({"pyproject.toml": '[build-system]\nrequires = ["setuptools>=64"]\n'
                             'build-backend = "setuptools.build_meta"\n[project]\n'
                             'name = "interbot-broken"\nversion = "1"\n'
                             '[project.entry-points."interbot.behaviors"]\n'
                             'Broken = "brokenplugin:SPEC"\n'
                             '[project.entry-points."interbot.percepts"]\n'
                             'broken = "brokenplugin:SPEC"\n',
           "brokenplugin/__init__.py": "raise RuntimeError('this plugin is broken')\n"}, package)
    site = tmp_path / "site"
    pip = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps",
                          "--no-build-isolation", "--target", str(site), str(package)],
                         capture_output=True, text=True, timeout=300)
    assert pip.returncode == 0, pip.stderr
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}
    listed = cli("behaviors", env=env)
    assert "Broken             NOT AVAILABLE: its plugin failed to load (RuntimeError: this " \
           "plugin is broken)" in listed.stdout
    assert "Survey" in listed.stdout
    assert "percept plugin 'broken' is not available" in cli("percepts", env=env).stdout
    ran = cli("run", "receptionist", "--fast", "--scenario", "visitor", "--quiet",
              "--data", str(tmp_path / "data"), env=env)
    assert ran.returncode == 0, ran.stdout + ran.stderr


def test_the_percept_list_names_every_declared_percept():
    text = (DOCS / "percepts.md").read_text(encoding="utf-8")
    missing = [name for name in percept_specs() if f"`{name}`" not in text]
    assert missing == []


COMMANDS = re.compile(r"<!-- commands: (?P<name>[\w-]+) -->\s*```sh\n(?P<body>.*?)```", re.DOTALL)


def command_blocks(name: str) -> list[list[str]]:
    """The shell lines of each `<!-- commands: name -->` block, in page order."""
    blocks = []
    for page in sorted(DOCS.glob("*.md")):
        for match in COMMANDS.finditer(page.read_text(encoding="utf-8")):
            if match["name"] == name:
                blocks.append([line for line in match["body"].splitlines() if line.strip()])
    return blocks


def run_commands(lines: list[str], folder: Path) -> list[subprocess.CompletedProcess]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = []
    for line in lines:
        words = line.split()
        assert words[0] == "interbot", line
        done.append(cli(*words[1:], env=env, cwd=folder))
        assert done[-1].returncode == 0, line + "\n" + done[-1].stdout + done[-1].stderr
    return done


def replace_inserts(sql: str, replacement: str) -> str:
    """database.sql with its INSERT statements into rooms and staff replaced by those of
    `replacement`, each where the old one stood."""
    ours = {}
    for table in ("rooms", "staff"):
        start = replacement.index(f"INSERT OR REPLACE INTO {table}")
        ours[table] = replacement[start:replacement.index(");\n", start) + 3]
    for table in ("rooms", "staff"):
        start = sql.index(f"INSERT OR REPLACE INTO {table}")
        end = sql.index(");\n", sql.index("VALUES", start)) + 3
        sql = sql[:start] + ours[table] + sql[end:]
    return sql


def test_the_walkthrough_from_a_slam_map_to_a_guide_run(tmp_path):
    """docs/navigation.md, *From your SLAM map to a guide run*, step by step."""
    from tests.applications.user_building import write_map
    write_map(tmp_path, places=False)             # as map_saver writes it: no places
    files = examples()["floor3"]
    (tmp_path / "floor3.places.yaml").write_text(files["floor3.places.yaml"])
    (tmp_path / "visit.toml").write_text(files["visit.toml"])
    new, check, run = command_blocks("floor3")
    run_commands(new, tmp_path)
    database = tmp_path / "floor3-guide" / "database.sql"
    database.write_text(replace_inserts(database.read_text(), files["rooms.sql"]))
    (checked,) = run_commands(check, tmp_path)
    assert "floor3-guide on robot horos: 0 errors, 0 warnings — OK" in checked.stdout
    run_commands(run, tmp_path)
    trace = (tmp_path / "visit.jsonl").read_text().splitlines()
    states = [json.loads(line)["to"] for line in trace if '"transition"' in line]
    assert states == ["Wait", "Attract", "AskWhat", "AskRoom", "GuideToRoom", "Goodbye",
                      "GoHome", "Wait"]
    import sqlite3
    with sqlite3.connect(tmp_path / "interbot-data" / "floor3-guide.sqlite") as db:
        assert db.execute("SELECT place, outcome FROM guide_runs").fetchall() == [
            ("room_b", "arrived")]
    # the page's two error lines, for the closed store room and a kitchen the map lacks
    database.write_text(database.read_text().replace(
        "    ('B', 'Room B', 'room_b', 'Raum B');",
        "    ('B', 'Room B', 'room_b', 'Raum B'),\n    ('X', 'Store room', 'store_room', 'Lager'),\n"
        "    ('K', 'Kitchen', 'kitchen', 'Küche');"))
    refused = cli(*check[0].split()[1:], env={**os.environ, "PYTHONPATH": str(ROOT)},
                  cwd=tmp_path)
    assert refused.returncode == 1
    page = (DOCS / "navigation.md").read_text(encoding="utf-8")
    shown = [line for line in page.splitlines() if line.startswith("floor3-guide/database.sql")]
    got = refused.stdout.splitlines()[:-1]
    assert len(shown) == len(got) == 2, refused.stdout
    for expected, line in zip(shown, got):
        head, _, tail = expected.partition("…")
        assert line.startswith(head) and line.endswith(tail), (expected, line)
