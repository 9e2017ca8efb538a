"""Parameters of the application (`<param>` inside `<application>`): written once, read in
conditions as `param.<name>` in the unit they were written in, passed to behaviors with
`from="param.<name>"`; behavior parameters accept any unit of their kind (pace="0.4m/s")."""
from __future__ import annotations

from pathlib import Path

import pytest

from applications.appfolder import inspect_folder
from applications.conditions import compile_condition, default_declarations
from applications.conditions.constants import ConstantError, parse_constant
from applications.exceptions import ConditionError
from applications.graph.model import Param, State
from applications.params import state_params
from behaviors.parameters import ParameterError, ParameterSpec, convert

GRAPH = '''<application name="params" initial="Wait" robot="horos">
  <param name="idle_timeout" value="2min"/>
  <param name="near" value="70cm"/>
  <param name="pace" value="0.4m/s"/>
  <state name="Wait" behavior="Idle">
    <transition to="Greet" when="people.new >= 1 and user.distance &lt; param.near"/>
  </state>
  <state name="Greet" behavior="FaceUser">
    <transition to="Wait" when="time_in_state > param.idle_timeout"/>
    <transition to="Wait" when="time_in_state &lt;= param.idle_timeout and not user.present"/>
  </state>
</application>
'''


def declarations(**written: str) -> dict:
    return {**default_declarations(),
            **{f"param.{name}": parse_constant(name, text) for name, text in written.items()}}


def folder_with(tmp_path: Path, graph: str) -> Path:
    (tmp_path / "graph.xml").write_text(graph)
    (tmp_path / "dialog.xml").write_text("<dialog/>\n")
    return tmp_path


def test_a_condition_reads_a_parameter_in_its_unit():
    condition = compile_condition("time_in_state > param.idle_timeout", None,
                                  declarations(idle_timeout="2min"))
    assert not condition.evaluate({}, 119.9) and condition.evaluate({}, 120.1)
    assert condition.names == frozenset()         # a constant, not a percept


def test_a_parameter_converts_exactly_as_the_written_number_would():
    near = compile_condition("user.distance < param.near", None, declarations(near="70cm"))
    written = compile_condition("user.distance < 0.7m")
    assert near.tree == written.tree


def test_true_false_and_text_parameters():
    flag = compile_condition("param.greet_all or people.new >= 1", None,
                             declarations(greet_all="true"))
    assert flag.evaluate({"people.new": 0}, 0.0)
    text = compile_condition('dialog.answer == param.word', None, declarations(word="yes"))
    assert text.evaluate({"dialog.answer": "yes"}, 0.0)
    assert not text.evaluate({"dialog.answer": "no"}, 0.0)


def test_a_parameter_of_the_wrong_kind_names_itself_and_the_fix():
    with pytest.raises(ConditionError, match=r"param.idle_timeout is 30s .*unit mismatch: "
                                             r"'user.distance' is a length"):
        compile_condition("user.distance < param.idle_timeout", None,
                          declarations(idle_timeout="30s"))
    with pytest.raises(ConditionError, match=r"'param.pace' is a speed \(0.4m/s\)"):
        compile_condition("time_in_state > param.pace", None, declarations(pace="0.4m/s"))


def test_an_unknown_parameter_gets_a_close_name_and_how_to_declare_one():
    with pytest.raises(ConditionError) as caught:
        compile_condition("time_in_state > param.idle_timout", None,
                          declarations(idle_timeout="30s"))
    assert "unknown parameter 'param.idle_timout'" in caught.value.reason
    assert "param.idle_timeout" in caught.value.reason
    assert '<param name="idle_timout" value="30s"/>' in caught.value.reason
    assert caught.value.offset == len("time_in_state > ")


def test_a_unit_spelled_out_is_refused_with_the_spelling_to_use():
    with pytest.raises(ConstantError, match='write value="1.5min"'):
        parse_constant("t", "1.5 minutes")
    with pytest.raises(ConstantError, match="unknown unit 'parsecs'"):
        parse_constant("t", "3parsecs")


def test_the_checker_accepts_parameters_and_proves_exclusivity_with_them(tmp_path):
    _, loaded, found = inspect_folder(folder_with(tmp_path, GRAPH))
    assert [str(d) for d in found] == []
    assert loaded.app.params["param.pace"].text == "0.4m/s"


def test_the_checker_reports_unknown_parameters_with_file_line_column(tmp_path):
    graph = GRAPH.replace("param.idle_timeout\"/>", "param.idle_timout\"/>")
    _, loaded, found = inspect_folder(folder_with(tmp_path, graph))
    assert loaded is None
    [problem] = [str(d) for d in found]
    line = graph.splitlines().index(next(l for l in graph.splitlines() if "idle_timout" in l)) + 1
    column = graph.splitlines()[line - 1].index("param.idle_timout") + 1
    assert problem.startswith(f"{tmp_path / 'graph.xml'}:{line}:{column}: error: in condition: "
                              "unknown parameter 'param.idle_timout' (did you mean "
                              "'param.idle_timeout'?)")


def test_an_application_parameter_is_a_fixed_value(tmp_path):
    graph = GRAPH.replace('<param name="near" value="70cm"/>',
                          '<param name="near" from="user.distance"/>')
    _, _, found = inspect_folder(folder_with(tmp_path, graph))
    assert any("a parameter of the application is a fixed value" in str(d) for d in found)


@pytest.mark.parametrize("text, metres_per_second", [
    ("0.4m/s", 0.4), ("40cm/s", 0.4), ("1.44km/h", 0.4), ("0.4", 0.4), (" 0.5 m/s ", 0.5)])
def test_a_speed_parameter_takes_any_speed_unit(text, metres_per_second):
    assert convert(ParameterSpec("speed"), text) == pytest.approx(metres_per_second)


def test_a_speed_in_an_unknown_unit_lists_the_units():
    with pytest.raises(ParameterError, match=r"unit 'mph' is not a speed with its unit; units: m/s, cm/s, km/h"):
        convert(ParameterSpec("speed"), "2mph")


def test_guide_person_takes_its_pace_from_an_application_parameter(tmp_path):
    state = State("Lead", "GuidePerson", (), False, None,
                  params=(Param("pace", None, "param.guide_pace"), Param("place", "room_n2")))
    constants = {"param.guide_pace": parse_constant("guide_pace", "45cm/s")}
    params, notes = state_params(state, "GuidePerson", {}, {}, tmp_path, None, constants)
    assert notes == [] and params["pace"] == pytest.approx(0.45)
    assert params["place"] == "room_n2"


def test_the_checker_refuses_a_parameter_of_the_wrong_kind_passed_to_a_behavior(tmp_path):
    graph = GRAPH.replace('<state name="Greet" behavior="FaceUser">',
                          '<state name="Greet" behavior="GoTo">\n'
                          '    <param name="place" value="room_n2"/>\n'
                          '    <param name="speed" from="param.near"/>')
    _, _, found = inspect_folder(folder_with(tmp_path, graph))
    assert any('from="param.near" (70cm): parameter \'speed\' of \'GoTo\' unit \'cm\' is not a speed'
               in str(d) for d in found), [str(d) for d in found]


def test_parameters_survive_an_scxml_round_trip(tmp_path):
    from applications.graph.scxml import export_scxml, import_scxml
    from applications.graph.writer import graph_xml
    _, loaded, _ = inspect_folder(folder_with(tmp_path, GRAPH))
    chart = export_scxml(loaded.app)
    assert "<data id=\"idle_timeout\" expr=\"'2min'\"/>" in chart
    (tmp_path / "chart.scxml").write_text(chart)
    back = import_scxml(tmp_path / "chart.scxml")
    assert {n: c.text for n, c in back.params.items()} == {
        "param.idle_timeout": "2min", "param.near": "70cm", "param.pace": "0.4m/s"}
    assert '<param name="near" value="70cm"/>' in graph_xml(back)


def test_interbot_percepts_lists_the_parameters_of_an_application(tmp_path, capsys):
    from applications.cli import main
    assert main(["percepts", "--app", str(folder_with(tmp_path, GRAPH))]) == 0
    listed = capsys.readouterr().out
    assert "param.idle_timeout   float [min]" in listed and "application parameter, 2min" in listed
