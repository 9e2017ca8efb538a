"""SCXML interchange: export → import gives the identical model, foreign markup survives, and
what the subset cannot express is reported with its line."""
from __future__ import annotations

from pathlib import Path

import pytest
from lxml import etree

from applications.appfolder import load_folder
from applications.cli import main
from applications.graph.loader import load_application
from applications.graph.scxml import SCXML, ScxmlImportError, export_scxml, import_scxml
from applications.graph.writer import graph_xml

QT = "http://www.qt.io/2015/02/scxml-ext"
QT_CHART = f"""<?xml version="1.0" encoding="UTF-8"?>
<scxml xmlns="{SCXML}" version="1.0" xmlns:qt="{QT}" name="hello" qt:editorversion="4.6.1"
       initial="Wait">
    <qt:editorinfo initialGeometry="-30;-20;-20;-20;40;40"/>
    <state id="Wait">
        <qt:editorinfo geometry="120;80;-60;-50;120;100"/>
        <onentry><send event="Idle" type="urn:interbot:behavior"/></onentry>
        <transition target="Talk" cond="people.count &gt;= 1">
            <qt:editorinfo endTargetFactors="50;50"/>
        </transition>
    </state>
    <final id="Talk">
        <onentry><send event="Survey"/></onentry>
    </final>
</scxml>
"""


def test_export_then_import_gives_the_identical_model(tmp_path: Path) -> None:
    original = load_application("survey")
    chart = tmp_path / "survey.scxml"
    chart.write_text(export_scxml(original))
    imported = import_scxml(chart)
    assert imported == original
    assert [t.priority for t in imported.states["CallBack"].transitions] == [1, 2]
    folder = tmp_path / "survey"
    folder.mkdir()
    (folder / "graph.xml").write_text(graph_xml(imported))
    assert load_application(folder) == original


def test_exported_document_is_scxml() -> None:
    root = etree.fromstring(export_scxml(load_application("survey")).encode())
    assert root.tag == f"{{{SCXML}}}scxml" and root.get("initial") == "Wait"
    states = root.findall(f"{{{SCXML}}}state")
    assert [s.get("id") for s in states] == ["Wait", "CreateAttention", "Interaction", "CallBack"]
    send = states[1].find(f"{{{SCXML}}}onentry/{{{SCXML}}}send")
    assert send.get("event") == "FaceUser"
    conds = [t.get("cond") for t in states[1].findall(f"{{{SCXML}}}transition")]
    assert conds[0] == "user.distance < 0.75m"


def test_qt_layout_markup_survives_import_and_export(tmp_path: Path) -> None:
    chart = tmp_path / "hello.scxml"
    chart.write_text(QT_CHART)
    application = import_scxml(chart)
    assert application.states["Talk"].final and application.states["Talk"].behavior == "Survey"
    written = graph_xml(application)
    assert f'xmlns:qt="{QT}"' in written and 'qt:editorversion="4.6.1"' in written
    assert 'endTargetFactors="50;50"' in written
    folder = tmp_path / "hello"
    folder.mkdir()
    (folder / "graph.xml").write_text(written)
    reloaded = load_application(folder)
    assert reloaded == application
    again = etree.fromstring(export_scxml(reloaded).encode())
    assert again.get(f"{{{QT}}}editorversion") == "4.6.1"
    wait = again.find(f"{{{SCXML}}}state")
    assert wait.find(f"{{{QT}}}editorinfo").get("geometry") == "120;80;-60;-50;120;100"
    transition = wait.find(f"{{{SCXML}}}transition")
    assert transition.find(f"{{{QT}}}editorinfo").get("endTargetFactors") == "50;50"


def test_outside_the_subset_is_reported_with_lines(tmp_path: Path) -> None:
    chart = tmp_path / "bad.scxml"
    chart.write_text(f"""<scxml xmlns="{SCXML}" initial="A">
  <state id="A">
    <onentry><send event="Idle"/></onentry>
    <transition event="go" target="B" cond="user.distance &lt; 30s"/>
  </state>
  <parallel id="P"/>
  <state id="B"/>
</scxml>""")
    with pytest.raises(ScxmlImportError) as caught:
        import_scxml(chart)
    found = [(d.location.line, d.message.split(":")[0]) for d in caught.value.diagnostics]
    assert (4, "event-triggered transitions are outside the subset") in found
    assert any(line == 4 and "unit mismatch" in d.message
               for d, (line, _) in zip(caught.value.diagnostics, found))
    assert any(line == 6 and "<parallel>" in message for line, message in
               [(d.location.line, d.message) for d in caught.value.diagnostics])
    assert any(line == 7 and "names no behavior" in message for line, message in
               [(d.location.line, d.message) for d in caught.value.diagnostics])


def test_export_and_import_commands(tmp_path: Path, capsys) -> None:
    chart = tmp_path / "survey.scxml"
    assert main(["export", "survey", "--format", "scxml", "-o", str(chart)]) == 0
    target = tmp_path / "copy"
    assert main(["import", str(chart), "-o", str(target)]) == 0
    assert "0 errors" in capsys.readouterr().out
    assert load_application(target) == load_application("survey")
    assert main(["import", str(chart), "-o", str(target)]) == 2      # no silent overwrite
    assert main(["import", str(chart), "-o", str(target), "--force"]) == 0


def test_a_final_state_with_transitions_round_trips(tmp_path: Path) -> None:
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "graph.xml").write_text(
        '<application name="f" initial="A"><state name="A" behavior="Idle" final="true">'
        '<transition to="A" when="survey.done"/></state></application>')
    original = load_application(folder)
    chart = tmp_path / "f.scxml"
    chart.write_text(export_scxml(original))
    assert 'interbot:final="true"' in chart.read_text()
    assert import_scxml(chart) == original


@pytest.mark.parametrize("written, fix", [("²", 'write interbot:priority="2"'),
                                          ("١", 'write interbot:priority="1"'),
                                          ("high", "not 'high'")])
def test_a_priority_in_other_digits_is_an_error_with_the_fix_not_a_crash(tmp_path: Path,
                                                                         written, fix) -> None:
    chart = tmp_path / "chart.scxml"
    chart.write_text(f"""<scxml xmlns="{SCXML}" xmlns:interbot="urn:interbot:graph" initial="A">
  <state id="A">
    <onentry><send event="Idle" type="urn:interbot:behavior"/></onentry>
    <transition target="A" cond="user.present" interbot:priority="{written}"/>
  </state>
</scxml>""", encoding="utf-8")
    with pytest.raises(ScxmlImportError) as caught:
        import_scxml(chart)
    (problem,) = caught.value.diagnostics
    assert (problem.location.line, problem.location.column) == (4, 67)
    assert fix in problem.message


def test_parameters_travel_as_the_behavior_sends_params(tmp_path: Path) -> None:
    """<param value> is expr="'text'", <param from lookup> is location + interbot:lookup, and an
    answer in a condition imports before the dialog that declares it is there."""
    original = load_folder("receptionist").app
    chart = tmp_path / "receptionist.scxml"
    chart.write_text(export_scxml(original))
    written = chart.read_text()
    assert ('<param name="say" location="answer.office" interbot:lookup="rooms.directions"/>'
            in written)
    imported = import_scxml(chart)
    assert [s.params for s in imported.states.values()] == \
        [s.params for s in original.states.values()]
    assert graph_xml(imported).count('from="answer.office" lookup="rooms.directions"') == 1
    texts = written.replace('location="answer.office" interbot:lookup="rooms.directions"',
                            '''expr="'it is the room &quot;N2&quot;'"''')
    chart.write_text(texts)
    (param,) = [p for s in import_scxml(chart).states.values() for p in s.params]
    assert (param.value, param.source) == ('it is the room "N2"', None)


def test_a_param_with_a_script_expression_is_refused_with_the_fix(tmp_path: Path) -> None:
    chart = tmp_path / "chart.scxml"
    chart.write_text(f"""<scxml xmlns="{SCXML}" initial="A">
  <state id="A">
    <onentry><send event="Say" type="urn:interbot:behavior">
      <param name="say" expr="greeting + name"/></send></onentry>
  </state>
</scxml>""", encoding="utf-8")
    with pytest.raises(ScxmlImportError) as caught:
        import_scxml(chart)
    (problem,) = caught.value.diagnostics
    assert problem.location.line == 4
    assert "expr must be a quoted text such as expr=\"'room_n2'\"" in problem.message
