"""Loading applications: finding them, the model, one-pass diagnostics, robots and behaviors."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from applications.exceptions import ApplicationError, UnknownApplicationError
from applications.graph.catalog import Catalog
from applications.graph.diagnostics import format_json
from applications.graph.loader import (check_application, find_application, load_application)
from applications.graph.model import Application, Location

SURVEY_GRAPH = """<?xml version="1.0"?>
<application name="mini" initial="Wait" robot="horos">
  <state name="Wait" behavior="Idle">
    <transition to="Face" when="time_in_state > 30s and people.new >= 1"/>
  </state>
  <state name="Face" behavior="FaceUser">
    <transition to="Wait" when="not user.present or time_in_state > 15s" priority="2"/>
    <transition to="Done" when="user.distance &lt; 0.75m" priority="1"/>
  </state>
  <state name="Done" behavior="Survey" final="true"/>
</application>
"""


def write_app(tmp_path: Path, text: str, name: str = "mini") -> Path:
    folder = tmp_path / name
    folder.mkdir()
    (folder / "graph.xml").write_text(text)
    return folder


def test_bundled_survey_loads_clean() -> None:
    application, diagnostics = check_application("survey")
    assert diagnostics == []
    assert application.initial == "Wait" and application.robot == "horos"
    assert application.states["CreateAttention"].behavior == "FaceUser"
    assert find_application("survey").name == "survey"


def test_model_from_a_folder(tmp_path: Path) -> None:
    folder = write_app(tmp_path, SURVEY_GRAPH)
    application = load_application(folder)
    assert isinstance(application, Application)
    assert application.folder == folder and application.graph_file == folder / "graph.xml"
    face = application.states["Face"]
    assert [t.target for t in face.ordered_transitions()] == ["Done", "Wait"]
    first = face.transitions[0]
    assert first.priority == 2 and first.when.startswith("not user.present")
    assert first.location == Location(str(folder / "graph.xml"), 7, 5)
    assert first.condition.evaluate({"user.present": False}, 0.0) is True
    assert application.states["Done"].final is True
    assert load_application(folder / "graph.xml") == application


def test_unknown_application_names_the_bundled_ones() -> None:
    with pytest.raises(UnknownApplicationError) as caught:
        find_application("no-such-app")
    assert "survey" in str(caught.value)


def test_errors_raise_with_all_diagnostics(tmp_path: Path) -> None:
    text = SURVEY_GRAPH.replace('to="Done"', 'to="Dne"').replace("people.new", "people.nwe")
    folder = write_app(tmp_path, text)
    with pytest.raises(ApplicationError) as caught:
        load_application(folder)
    messages = [str(d) for d in caught.value.diagnostics]
    assert any(":8:21: error: transition to unknown state 'Dne' (did you mean 'Done'?)" in m
               for m in messages)
    assert any(":4:57: error: in condition: unknown percept 'people.nwe'" in m for m in messages)


def test_warnings_alone_do_not_refuse(tmp_path: Path) -> None:
    text = SURVEY_GRAPH.replace(' final="true"', "")
    folder = write_app(tmp_path, text)
    application, diagnostics = check_application(folder)
    assert application is not None
    assert [d.code for d in diagnostics] == ["no-way-out"]
    assert load_application(folder).name == "mini"


def test_json_diagnostics(tmp_path: Path) -> None:
    folder = write_app(tmp_path, SURVEY_GRAPH.replace('initial="Wait"', 'initial="Wiat"'))
    _, diagnostics = check_application(folder)
    document = json.loads(format_json(diagnostics))
    assert document["errors"] == 1
    entry = document["diagnostics"][0]
    assert (entry["line"], entry["column"], entry["code"]) == (2, 35, "unknown-initial")


class Spec:
    def __init__(self, name: str, realizations: dict, requires=frozenset()):
        self.name, self.realizations, self.requires = name, realizations, frozenset(requires)


def catalog_for(robot: str | None) -> Catalog:
    behaviors = {"Idle": Spec("Idle", {"any": frozenset()}),
                 "FaceUser": Spec("FaceUser", {"head": frozenset({"pan_tilt"}),
                                               "body": frozenset({"turn_in_place"})}),
                 "Survey": Spec("Survey", {"screen": frozenset({"touch_screen"})},
                                requires={"touch_screen"})}
    robots = {"horos": frozenset({"pan_tilt", "touch_screen"}), "perses": frozenset(),
              "b21": frozenset({"turn_in_place", "touch_screen"})}
    return Catalog(behaviors, tuple(robots), robot, robots.get(robot))


def test_behaviors_are_checked_against_the_chosen_robot(tmp_path: Path) -> None:
    folder = write_app(tmp_path, SURVEY_GRAPH)
    assert check_application(folder, catalog=catalog_for)[1] == []
    assert check_application(folder, robot="b21", catalog=catalog_for)[1] == []
    _, diagnostics = check_application(folder, robot="perses", catalog=catalog_for)
    assert [(d.location.line, d.code) for d in diagnostics] == [
        (6, "robot-lacks-capability"), (10, "robot-lacks-capability")]
    assert "needs touch_screen, which robot 'perses' lacks" in diagnostics[1].message
    _, diagnostics = check_application(folder, robot="robby", catalog=catalog_for)
    assert diagnostics[0].code == "unknown-robot" and "horos" in diagnostics[0].message


def test_real_registry_knows_the_survey_behaviors() -> None:
    from applications.graph.catalog import load_catalog
    catalog = load_catalog("horos")
    assert catalog.behaviors is not None, "the behavior registry must load"
    assert {"Idle", "FaceUser", "Survey", "CallBack"} <= set(catalog.behaviors)
    assert check_application("survey", robot="perses")[1] == []


def test_a_transition_without_when_is_always_taken_and_checked_as_such(tmp_path: Path) -> None:
    folder = write_app(tmp_path, """<application name="w" initial="A">
  <state name="A" behavior="Idle">
    <transition to="B"/>
    <transition to="A" when="survey.done"/>
  </state>
  <state name="B" behavior="Idle" final="true"/>
</application>""")
    _, diagnostics = check_application(folder)
    assert [(d.location.line, d.code) for d in diagnostics] == [(4, "overlap")]
    assert "e.g. when survey.done = true" in diagnostics[0].message


def test_foreign_namespace_markup_is_allowed_and_kept(tmp_path: Path) -> None:
    folder = write_app(tmp_path, SURVEY_GRAPH.replace(
        '<state name="Done"', '<x:note xmlns:x="urn:x">hi</x:note><state x:pos="1,2" '
        'xmlns:x="urn:x" name="Done"'))
    application, diagnostics = check_application(folder)
    assert diagnostics == []
    assert application.foreign.elements[0].startswith("<x:note")
    assert application.states["Done"].foreign.attributes == (("{urn:x}pos", "1,2"),)


def test_misplaced_elements_say_where_they_belong(tmp_path: Path) -> None:
    folder = write_app(tmp_path, """<application name="w" initial="A">
  <transition to="A" when="survey.done"/>
  <state name="A" behavior="Idle" final="true"><state name="B" behavior="Idle"/></state>
</application>""")
    _, diagnostics = check_application(folder)
    assert [(d.location.line, d.location.column, d.message) for d in diagnostics] == [
        (2, 3, "<transition> cannot stand inside <application>: it belongs inside <state>"),
        (3, 48, "<state> cannot stand inside <state>: it belongs inside <application>")]


def test_condition_errors_on_a_later_line_of_a_multi_line_attribute(tmp_path: Path) -> None:
    folder = write_app(tmp_path, """<application name="w" initial="A">
  <state name="A" behavior="Idle">
    <transition to="A" when="survey.done and
        user.distnce &lt; 1m"/>
  </state>
</application>""")
    _, diagnostics = check_application(folder)
    assert diagnostics[0].location.line == 4 and diagnostics[0].location.column == 9
    assert "unknown percept 'user.distnce'" in diagnostics[0].message


def test_the_schema_is_shipped_and_backs_up_the_reader(tmp_path: Path) -> None:
    from applications.graph.schema import SCHEMA_FILE, schema_problems
    from applications.graph.xmlsafe import parse_xml
    assert SCHEMA_FILE.is_file()
    assert schema_problems(parse_xml(find_application("survey") / "graph.xml")) == []
    folder = write_app(tmp_path, """<application name="w" initial="A">
  <state name="A" behavior="Idle" final="true">stray words</state>
</application>""")
    _, diagnostics = check_application(folder)
    assert [(d.location.line, d.code) for d in diagnostics] == [(2, "stray-text")]
    assert "stray text 'stray words' inside <state>" in diagnostics[0].message
    problems = schema_problems(parse_xml(folder / "graph.xml"))
    assert problems and problems[0][0] == 2      # the schema agrees, with a vaguer message


def test_columns_ignore_a_byte_order_mark_and_count_characters(tmp_path: Path) -> None:
    folder = tmp_path / "bom"
    folder.mkdir()
    text = ('<application name="é" initial="Wiat"><state name="Wait" behavior="Idle" '
            'final="true"/></application>')
    (folder / "graph.xml").write_bytes(b"\xef\xbb\xbf" + text.encode("utf-8"))
    _, diagnostics = check_application(folder)
    assert (diagnostics[0].location.line, diagnostics[0].location.column) == (1, 32)
