import pytest

from applications.dialog import load_dialog
from applications.exceptions import ApplicationError
from applications.graph.loader import find_application


def test_bundled_dialog_content_and_override():
    dialog = load_dialog(find_application("survey") / "dialog.xml")
    assert [q["id"] for q in dialog.questions] == ["q1", "q2", "q3"]
    assert dialog.questions[1]["buttons"] == ["1", "2", "3", "4", "5"]
    far = dialog.choose("CreateAttention", "FaceUser", {"user.distance": 4.0})
    near = dialog.choose("CreateAttention", "FaceUser", {"user.distance": 1.0})
    absent = dialog.choose("CreateAttention", "FaceUser", {"user.distance": None})
    assert far.behavior == "AttractAttention" and far.overridden
    assert near.behavior == "FaceUser" and not near.overridden
    assert absent.behavior == "FaceUser"
    assert "Please come closer" in near.params["say"]
    assert dialog.choose("Wait", "Idle", {}).behavior == "Idle"


def test_bad_dialog_reports_every_problem_with_file_and_line(tmp_path):
    path = tmp_path / "dialog.xml"
    path.write_text('<dialog>\n<behavior name="Survey">\n<question id="q1"/>\n</behavior>\n'
                    '<override state="Wait" when="user.distance &lt;" behavior="Idle"/>\n<oops/>\n</dialog>\n')
    with pytest.raises(ApplicationError) as caught:
        load_dialog(path)
    message = str(caught.value)
    assert f"{path}:3:1: error: <question> needs at least one <answer>" in message
    assert f"{path}:3:1: error: <question> needs a non-empty text=" in message
    # the condition's problem is pointed at in the line (column of the missing operand)
    assert f"{path}:5:48: error: in condition:" in message
    assert f"{path}:6:1: error: unknown element <oops>" in message
    assert len(caught.value.diagnostics) == 4


def test_dialog_with_a_doctype_is_refused(tmp_path):
    path = tmp_path / "dialog.xml"
    path.write_text('<?xml version="1.0"?>\n<!DOCTYPE d [<!ENTITY x "boom">]>\n<dialog>&x;</dialog>\n')
    with pytest.raises(ApplicationError):
        load_dialog(path)


def test_overrides_are_checked_against_the_graph_and_the_registry(tmp_path, capsys):
    import shutil

    from applications.cli import main

    folder = tmp_path / "survey"
    shutil.copytree(find_application("survey"), folder)
    dialog = folder / "dialog.xml"
    dialog.write_text(dialog.read_text().replace(
        '<override state="CreateAttention" when="user.distance > 2.5m" behavior="AttractAttention"/>',
        '<override state="CreateAtention" when="user.distance > 2.5m" behavior="AtractAttention"/>'))
    assert main(["check", str(folder)]) == 1
    out = capsys.readouterr().out
    assert "unknown state 'CreateAtention' (did you mean 'CreateAttention'?)" in out
    assert "unknown behavior 'AtractAttention' (did you mean 'AttractAttention'?)" in out
    assert f"{dialog}:" in out
    assert main(["run", str(folder), "--fast", "--duration", "1", "--data", str(tmp_path)]) == 1
