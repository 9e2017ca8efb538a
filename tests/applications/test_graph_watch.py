"""Hot reload: an edit is noticed once; a clean edit gives a new model, a broken one its errors."""
from __future__ import annotations

import os
from types import SimpleNamespace
from pathlib import Path

from applications.graph.model import Application
from applications.graph.watch import ApplicationWatcher
from applications.statemachine import StateMachine

GRAPH = """<application name="w" initial="A">
  <state name="A" behavior="Idle"><transition to="B" when="people.count >= 1"/></state>
  <state name="B" behavior="Idle" final="true"/>
</application>
"""


def write(path: Path, text: str, tick: int) -> None:
    path.write_text(text)
    os.utime(path, ns=(tick * 1_000_000_000, tick * 1_000_000_000))   # a distinct mtime


def test_watcher_reports_nothing_until_a_file_changes(tmp_path: Path) -> None:
    graph = tmp_path / "graph.xml"
    write(graph, GRAPH, 1)
    watcher = ApplicationWatcher(tmp_path)
    assert watcher.poll() is None
    write(graph, GRAPH.replace('name="B"', 'name="C"').replace('to="B"', 'to="C"'), 2)
    reloaded = watcher.poll()
    assert isinstance(reloaded.app, Application) and set(reloaded.app.states) == {"A", "C"}
    assert watcher.poll() is None
    in_a, in_b = StateMachine(reloaded.app, 0.0), StateMachine(reloaded.app, 0.0)
    in_b.state = SimpleNamespace(name="B")          # a state the new version no longer has
    assert in_a.replace(reloaded.app, 1.0) is False and in_a.state.name == "A"
    assert in_b.replace(reloaded.app, 1.0) is True and in_b.state.name == "A"


def test_an_edit_with_errors_returns_its_errors_once(tmp_path: Path) -> None:
    graph = tmp_path / "graph.xml"
    write(graph, GRAPH, 1)
    watcher = ApplicationWatcher(tmp_path)
    write(graph, GRAPH.replace('to="B"', 'to="X"'), 2)
    problems = watcher.poll()
    assert isinstance(problems, list) and problems[0].code == "unknown-state"
    assert watcher.poll() is None
    write(graph, GRAPH, 3)
    assert isinstance(watcher.poll().app, Application)


def test_a_new_dialog_file_counts_as_a_change_and_removal_is_an_error(tmp_path: Path) -> None:
    graph = tmp_path / "graph.xml"
    write(graph, GRAPH, 1)
    watcher = ApplicationWatcher(tmp_path)
    write(tmp_path / "dialog.xml", "<dialog/>", 2)
    assert isinstance(watcher.poll().app, Application)
    graph.unlink()
    problems = watcher.poll()
    assert "graph.xml was removed" in problems[0].message
