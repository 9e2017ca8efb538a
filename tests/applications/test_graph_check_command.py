"""`interbot check`: exit codes, text and JSON output, through the real command line."""
from __future__ import annotations

import json
from pathlib import Path

from applications.cli import main

BROKEN = Path(__file__).parent / "broken"


SURVEY_DIALOG = ('<dialog><behavior name="Survey"><question id="q1" text="Fine?">'
                 '<answer>yes</answer><answer>no</answer></question></behavior></dialog>')


def app_from(tmp_path: Path, corpus_file: str) -> Path:
    """An application folder around a corpus graph; its dialog and database are sound."""
    from applications.database import ANSWERS_TABLE_SQL
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "graph.xml").write_bytes((BROKEN / corpus_file).read_bytes())
    (folder / "dialog.xml").write_text(SURVEY_DIALOG)
    (folder / "database.sql").write_text(ANSWERS_TABLE_SQL)
    return folder


def test_clean_application_exits_0(capsys) -> None:
    assert main(["check", "survey"]) == 0
    assert "survey on robot horos: 0 errors, 0 warnings" in capsys.readouterr().out
    assert main(["check", "survey", "--robot", "perses"]) == 0


def test_errors_exit_1_and_print_file_line_col(tmp_path: Path, capsys) -> None:
    folder = app_from(tmp_path, "unknown_initial_and_target.xml")
    assert main(["check", str(folder)]) == 1
    out = capsys.readouterr().out
    assert f"{folder}/graph.xml:1:37: error: initial state 'Wiat' is not defined" in out
    assert "2 errors" in out


def test_warnings_alone_exit_0(tmp_path: Path, capsys) -> None:
    folder = app_from(tmp_path, "warnings_only.xml")
    assert main(["check", str(folder)]) == 0
    assert ": warning: " in capsys.readouterr().out


def test_json_output(tmp_path: Path, capsys) -> None:
    folder = app_from(tmp_path, "overlaps.xml")
    assert main(["check", str(folder), "--json"]) == 1
    document = json.loads(capsys.readouterr().out)
    assert document["errors"] == 4 and document["warnings"] == 0
    first = document["diagnostics"][0]
    assert (first["line"], first["column"], first["severity"], first["code"]) == \
        (4, 5, "error", "overlap")
    assert "time_in_state = 16 s" in first["message"]


def test_unknown_application_or_robot_exit_2(capsys) -> None:
    assert main(["check", "no-such-app"]) == 2
    assert "survey" in capsys.readouterr().err
    assert main(["check", "survey", "--robot", "robby"]) == 2
    assert "horos" in capsys.readouterr().err
