"""Every example in docs/ is run: the application examples are written out and checked (and run
where they bring a scenario); the plugin package of docs/plugins.md is built, installed into a
folder of its own and used by an application; the percept list names every declared percept."""
from __future__ import annotations

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
