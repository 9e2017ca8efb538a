"""A state that asks questions and can only be left by an answer waits for ever when the visitor
walks away: the checker warns, at the state, with a way out to add."""
from __future__ import annotations

from pathlib import Path

import pytest

from applications.appfolder import inspect_folder

GRAPH = '''<application name="asker" initial="Wait" robot="horos">
  <state name="Wait" behavior="Idle">
    <transition to="Ask" when="people.new >= 1"/>
  </state>
  <state name="Ask" behavior="Ask">
    <transition to="Wait" when="{way_out}"/>
  </state>
</application>
'''
DIALOG = '''<dialog><state name="Ask"><question id="q" text="Another one?">
  <answer value="yes">Yes</answer><answer value="no">No</answer></question></state></dialog>
'''
SQL = ("CREATE TABLE IF NOT EXISTS answers (id INTEGER PRIMARY KEY AUTOINCREMENT, run_id TEXT "
       "NOT NULL, robot TEXT NOT NULL, session INTEGER NOT NULL, question TEXT NOT NULL, answer "
       "TEXT NOT NULL, robot_time REAL NOT NULL, wall_time REAL NOT NULL);\n")


def check(tmp_path: Path, way_out: str) -> list[str]:
    (tmp_path / "graph.xml").write_text(GRAPH.format(way_out=way_out))
    (tmp_path / "dialog.xml").write_text(DIALOG)
    (tmp_path / "database.sql").write_text(SQL)
    _, _, found = inspect_folder(tmp_path)
    return [str(d) for d in found]


def test_an_asking_state_left_only_by_an_answer_gets_a_warning(tmp_path):
    [found] = check(tmp_path, "behavior.done")
    assert found.startswith(f"{tmp_path / 'graph.xml'}:5:")
    assert "warning: state 'Ask' asks questions (Ask) and is left only by an answer" in found
    assert '<transition to="Wait" when="not user.present or time_in_state > 40s"/>' in found


@pytest.mark.parametrize("way_out", ["behavior.done or time_in_state > 40s",
                                     "behavior.done or not user.present",
                                     "user.left"])
def test_a_timeout_or_the_visitor_leaving_is_a_way_out(tmp_path, way_out):
    assert check(tmp_path, way_out) == []
