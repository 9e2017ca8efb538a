"""The application folder checked as a whole: per-state dialog, parameters, answers, database."""
from __future__ import annotations

from pathlib import Path

import pytest

from applications.appfolder import inspect_folder, load_folder
from applications.cli import main
from applications.database import ANSWERS_TABLE_SQL
from applications.exceptions import ApplicationError

GRAPH = """<application name="t" initial="Ask" robot="horos">
  <state name="Ask" behavior="Ask">
    <transition to="Tell" when="behavior.done"/><transition to="Ask" when="not behavior.done and time_in_state > 60s"/>
  </state>
  <state name="Tell" behavior="Say">
{params}    <transition to="Ask" when="behavior.done"/>
  </state>
</application>
"""
DIALOG = """<dialog>
  <state name="Ask">
    <question id="office" text="Which office?">
      <answer value="N1">Weber</answer><answer value="N2">Gross</answer>
    </question>
  </state>
  <state name="Tell"><say>Bye {{answer.office}}</say></state>
{extra}</dialog>
"""
ROOMS = ("CREATE TABLE IF NOT EXISTS rooms (name TEXT PRIMARY KEY, place TEXT);\n"
         "INSERT OR REPLACE INTO rooms VALUES ('N1', 'room_n1'), ('N2', 'room_n2');\n")


def folder(tmp_path: Path, params: str = "", extra: str = "", database: str | None = None) -> Path:
    app = tmp_path / "t"
    app.mkdir(exist_ok=True)
    (app / "graph.xml").write_text(GRAPH.format(params=params))
    (app / "dialog.xml").write_text(DIALOG.format(extra=extra))
    if database is not False:
        (app / "database.sql").write_text(ANSWERS_TABLE_SQL + "\n" + ROOMS
                                          if database is None else database)
    return app


def problems(app: Path) -> list[str]:
    return [f"{d.location.line}:{d.location.column}: {d.severity}: {d.message}"
            for d in inspect_folder(app)[2]]


def test_a_sound_folder_loads_with_answers_declared(tmp_path):
    loaded = load_folder(folder(tmp_path))
    assert loaded.records_answers
    assert loaded.dialog.params_for("Tell", "Say")["say"] == "Bye {answer.office}"
    assert problems(tmp_path / "t") == []


def test_state_content_wins_over_the_behavior_default(tmp_path):
    app = folder(tmp_path, extra='  <behavior name="Say"><say>Default</say></behavior>\n')
    dialog = load_folder(app).dialog
    assert dialog.params_for("Tell", "Say")["say"] == "Bye {answer.office}"
    assert dialog.params_for("Other", "Say")["say"] == "Default"


def test_unknown_and_ill_typed_parameters_point_at_the_line(tmp_path):
    app = folder(tmp_path, params='    <param name="sya" value="hi"/>\n')
    assert any(p.startswith("6:5: error: behavior 'Say' has no parameter 'sya' (did you mean "
                            "'say'?)") for p in problems(app))
    (app / "graph.xml").write_text(GRAPH.format(params='').replace(
        'behavior="Say">', 'behavior="Wait">\n    <param name="duration" value="3"/>'))
    assert any("parameter 'duration' of 'Wait' '3' has no unit; write a duration with its unit"
               in p for p in problems(app))


def test_a_parameter_from_an_answer_and_a_database_lookup(tmp_path):
    app = folder(tmp_path, params='    <param name="say" from="answer.ofice"/>\n')
    assert any("from=\"answer.ofice\": unknown percept (did you mean 'answer.office'?)" in p
               for p in problems(app))
    app = folder(tmp_path, params='    <param name="say" from="answer.office" lookup="room.place"/>\n')
    assert any("lookup=\"room.place\": database.sql has no table 'room'; tables:" in p
               for p in problems(app))
    app = folder(tmp_path, params='    <param name="say" from="answer.office" lookup="rooms.place"/>\n')
    assert problems(app) == []


def test_a_required_parameter_missing_is_an_error(tmp_path):
    app = folder(tmp_path)
    (app / "dialog.xml").write_text(DIALOG.format(extra="").replace(
        '<state name="Tell"><say>Bye {answer.office}</say></state>', ""))
    assert any("state 'Tell' runs Say, which needs <say>" in p for p in problems(app))
    (app / "dialog.xml").write_text("<dialog/>")
    assert any("state 'Ask' runs Ask, which needs questions" in p for p in problems(app))


def test_empty_texts_duplicate_ids_and_unknown_placeholders_are_refused(tmp_path):
    app = folder(tmp_path, extra='  <behavior name="FaceUser"><say>  </say></behavior>\n'
                                 '  <behavior name="Survey"><question id="office" text="Again?">'
                                 '<answer>yes</answer></question></behavior>\n')
    found = problems(app)
    assert any(p.startswith("8:29: error: <say> is empty") for p in found)
    assert any("duplicate question id 'office' (first at line 3)" in p for p in found)
    (app / "dialog.xml").write_text(DIALOG.format(extra="").replace("{answer.office}",
                                                                    "{answer.ofice}"))
    assert any("unknown percept '{answer.ofice}' in the text (did you mean 'answer.office'?)"
               in p for p in problems(app))


def test_an_application_that_records_answers_needs_its_database(tmp_path):
    app = folder(tmp_path, database=False)
    assert any("records answers (state 'Ask' (Ask)) but has no database.sql" in p
               for p in problems(app))
    (app / "database.sql").write_text("CREATE TABLE answers (id INTEGER);\nCRATE TABLE x (a);\n")
    assert any(p.startswith('2:1: error: near "CRATE": syntax error') for p in problems(app))
    (app / "database.sql").write_text("CREATE TABLE answers (id INTEGER);\n")
    assert any("CREATE TABLE answers" in p for p in problems(app))     # not run twice safely
    (app / "database.sql").write_text("CREATE TABLE IF NOT EXISTS answers (id INTEGER);\n")
    assert any("does not create an answers table with the columns run_id" in p
               for p in problems(app))


def test_run_refuses_what_check_refuses(tmp_path, capsys):
    app = folder(tmp_path, database=False)
    assert main(["check", str(app)]) == 1
    assert main(["run", str(app), "--fast", "--duration", "1", "--data", str(tmp_path)]) == 1
    with pytest.raises(ApplicationError):
        load_folder(app)


def test_interbot_new_makes_a_folder_that_checks_and_runs(tmp_path, capsys):
    target = tmp_path / "kiosk"
    assert main(["new", str(target)]) == 0
    assert main(["check", str(target)]) == 0
    trace = tmp_path / "kiosk.jsonl"
    assert main(["run", str(target), "--fast", "--trace", str(trace), "--data",
                 str(tmp_path / "data"), "--quiet"]) == 0
    from applications.trace import read_trace
    states = [e["to"] for e in read_trace(trace) if e["kind"] == "transition"]
    assert states == ["Wait", "Greet", "Ask", "Thanks", "Wait"]
    assert main(["new", str(target)]) == 2                 # never overwrites
    assert main(["new", str(tmp_path / "9lives")]) == 2    # not a name


def test_interbot_new_from_copies_an_application_under_its_new_name(tmp_path, capsys):
    target = tmp_path / "floor3-guide"
    assert main(["new", str(target), "--from", "guide"]) == 0
    assert main(["check", str(target)]) == 0
    assert '<application name="floor3-guide"' in (target / "graph.xml").read_text()
    bundled = load_folder("guide").folder
    for name in ("dialog.xml", "database.sql"):
        assert (target / name).read_bytes() == (bundled / name).read_bytes()
    assert main(["new", str(target), "--from", "guide"]) == 2       # never overwrites
    assert main(["new", str(tmp_path / "other"), "--from", "atlantis"]) == 2


def test_listing_commands_show_parameters_percepts_and_version(capsys):
    assert main(["behaviors"]) == 0
    out = capsys.readouterr().out
    assert "parameter say: text, required" in out and "records answers" in out
    assert main(["percepts", "--app", "receptionist"]) == 0
    out = capsys.readouterr().out
    assert 'answer.office        str one of "N1", "N2", "N3", "S4", "unknown"' in out
    assert "user.distance        float [m] 0…30" in out
    with pytest.raises(SystemExit) as leaving:
        main(["--version"])
    assert leaving.value.code == 0 and capsys.readouterr().out.startswith("interbot ")


@pytest.mark.parametrize("written, says", [
    ("N9", "'answer.office' is never 'N9'; its values: \"N1\", \"N2\""),
    ("n2", "'answer.office' is never 'n2' (did you mean 'N2'?)"),
])
def test_an_answer_the_dialog_does_not_offer_is_an_error_at_its_column(tmp_path, written, says):
    app = folder(tmp_path)
    graph = app / "graph.xml"
    graph.write_text(graph.read_text().replace(
        '<transition to="Tell" when="behavior.done"/>',
        f'<transition to="Tell" when="answer.office == \'{written}\'"/>'))
    # line 3, column 50: the quoted value inside the condition
    assert problems(app) == [f"3:50: error: in condition: {says}"
                             + ("" if written == "N9" else '; its values: "N1", "N2"')]
