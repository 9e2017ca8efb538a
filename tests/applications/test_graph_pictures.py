"""Pictures of the state graph: ascii and dot always; svg/png only through Graphviz."""
from __future__ import annotations

import shutil

import pytest

from applications.cli import main
from applications.graph.loader import load_application
from applications.graph.pictures import GraphvizMissingError, render, to_ascii, to_dot


def test_ascii_marks_initial_behaviors_priorities_and_conditions() -> None:
    text = to_ascii(load_application("survey"))
    assert "-> [Wait]  behavior Idle  (initial)" in text
    assert "[1] --> Interaction   when user.distance < 0.75m" in text
    assert "--> CallBack   when not user.present and not survey.done" in text


def test_dot_has_every_state_and_edge_with_labels() -> None:
    application = load_application("survey")
    text = to_dot(application)
    assert text.startswith('digraph "survey" {')
    assert '__start -> "Wait";' in text
    for state in application.states.values():
        assert f'"{state.name}" [label="{state.name}\\n{state.behavior}"' in text
    edges = [line for line in text.splitlines() if "->" in line and "__start" not in line]
    assert len(edges) == sum(len(s.transitions) for s in application.states.values())
    assert '"CreateAttention" -> "Interaction" [label="[1] user.distance < 0.75m"];' in text


def test_final_states_get_a_double_border(tmp_path) -> None:
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "graph.xml").write_text(
        '<application name="a" initial="A"><state name="A" behavior="Idle">'
        '<transition to="B" when="survey.done"/></state>'
        '<state name="B" behavior="Idle" final="true"/></application>')
    application = load_application(folder)
    assert '"B" [label="B\\nIdle", peripheries=2];' in to_dot(application)
    assert "(final)" in to_ascii(application)


def test_svg_without_graphviz_says_how_to_install_it(capsys, tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("PATH", str(tmp_path))          # a machine without Graphviz's dot
    with pytest.raises(GraphvizMissingError) as caught:
        render(load_application("survey"), "svg")
    assert "apt-get install graphviz" in str(caught.value)
    assert main(["show", "survey", "--format", "svg"]) == 1
    assert "apt-get install graphviz" in capsys.readouterr().err


def test_svg_with_graphviz(tmp_path) -> None:
    assert shutil.which("dot"), "Graphviz's dot is needed: .ci/run installs it (apt-get install graphviz)"
    target = tmp_path / "survey.svg"
    assert main(["show", "survey", "--format", "svg", "-o", str(target)]) == 0
    assert b"<svg" in target.read_bytes() and b"CreateAttention" in target.read_bytes()


def test_show_command_prints_ascii_and_writes_dot(tmp_path, capsys) -> None:
    assert main(["show", "survey"]) == 0
    assert "behavior FaceUser" in capsys.readouterr().out
    target = tmp_path / "g.dot"
    assert main(["show", "survey", "--format", "dot", "-o", str(target)]) == 0
    assert target.read_text().startswith('digraph "survey"')


def test_show_draws_a_graph_with_errors_and_prints_them(tmp_path, capsys) -> None:
    folder = tmp_path / "broken"
    folder.mkdir()
    (folder / "graph.xml").write_text(
        '<application name="b" initial="A"><state name="A" behavior="Idle">'
        '<transition to="Nowhere" when="survey.done"/></state></application>')
    assert main(["show", str(folder)]) == 1
    captured = capsys.readouterr()
    assert "--> Nowhere" in captured.out
    assert "transition to unknown state 'Nowhere'" in captured.err


def test_show_writes_the_format_the_file_name_asks_for(tmp_path, capsys) -> None:
    assert shutil.which("dot"), "Graphviz's dot is needed: .ci/run installs it (apt-get install graphviz)"
    png, dot = tmp_path / "survey.png", tmp_path / "survey.gv"
    assert main(["show", "survey", "-o", str(png)]) == 0
    assert png.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
    assert main(["show", "survey", "-o", str(dot)]) == 0
    assert dot.read_text().startswith('digraph "survey"')
    capsys.readouterr()
    assert main(["show", "survey", "--format", "svg", "-o", str(tmp_path / "x.png")]) == 2
    assert "--format svg, but the file name" in capsys.readouterr().err
    assert main(["show", "survey", "-o", str(tmp_path / "x.pdf")]) == 2
    assert "cannot tell the picture's format from '.pdf'" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "x.pdf").exists()
