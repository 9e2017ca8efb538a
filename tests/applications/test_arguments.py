"""Mistaken arguments: one line naming the argument, what is wrong and what is allowed, exit 2,
before the robot is opened (the robot end at --port never sees a connection)."""
from __future__ import annotations

import pytest

from applications.cli import main
from tests.faults.peer import ScriptedPioneer


@pytest.fixture(scope="module")
def robot_end():
    peer = ScriptedPioneer()
    yield peer
    peer.shutdown()


@pytest.fixture
def pause_app(tmp_path):
    folder = tmp_path / "pause"
    folder.mkdir()
    (folder / "graph.xml").write_text(
        '<application name="pause" initial="Wait" robot="horos">'
        '<state name="Wait" behavior="Idle" final="true"/></application>')
    return folder


MISTAKES = [
    # (arguments after `run APP --port URL`, the argument named, a word of what is allowed)
    (["--seed", "-1"], "--seed", "0 .. 4294967295"),
    (["--seed", "1.5"], "--seed", "0 .. 4294967295"),
    (["--trace", "{tmp}/missing/trace.jsonl"], "--trace", "existing folder"),
    (["--trace", "/dev/full"], "--trace", "room to grow"),
    (["--trace", "{tmp}"], "--trace", "file path"),
    (["--data", "{app}/graph.xml"], "--data", "folder"),
    (["--data", "{app}/graph.xml/deeper"], "--data", "folder"),
    (["--duration", "-5"], "--duration", "finite number of seconds > 0"),
    (["--duration", "0"], "--duration", "finite number of seconds > 0"),
    (["--duration", "nan"], "--duration", "finite number of seconds > 0"),
    (["--duration", "inf"], "--duration", "finite number of seconds > 0"),
    (["--duration", "ten"], "--duration", "seconds > 0"),
]


@pytest.mark.parametrize("extra,argument", [(["--fast"], "--fast"),
                                            (["--scenario", "complete"], "--scenario")])
def test_simulation_options_with_a_port_are_refused_before_the_robot_opens(
        robot_end, pause_app, capsys, extra, argument):
    before = robot_end.connections
    code = main(["run", str(pause_app), "--port", robot_end.url, *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and f"argument {argument}" in err[0], err
    assert robot_end.connections == before


@pytest.mark.parametrize("extra,argument,allowed", MISTAKES)
def test_a_mistaken_run_argument_is_one_line_and_exit_2_before_the_robot_opens(
        robot_end, pause_app, tmp_path, capsys, extra, argument, allowed):
    extra = [a.format(tmp=tmp_path, app=pause_app) for a in extra]
    before = robot_end.connections
    with pytest.raises(SystemExit) as exit_:
        main(["run", str(pause_app), "--port", robot_end.url, *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert exit_.value.code == 2
    assert len(err) == 1, err
    assert f"argument {argument}" in err[0] and allowed in err[0]
    assert "Traceback" not in err[0]
    assert robot_end.connections == before


@pytest.mark.parametrize("argv,argument,allowed", [
    (["emulate", "p2os", "--tcp", "99999"], "--tcp", "0 .. 65535"),
    (["emulate", "p2os", "--tcp", "-1"], "--tcp", "0 .. 65535"),
    (["emulate", "p2os", "--seed", "-1"], "--seed", "0 .. 4294967295"),
    (["export", "survey", "-o", "{tmp}/missing/survey.scxml"], "-o/--output", "existing folder"),
    (["show", "survey", "-o", "{tmp}/missing/survey.txt"], "-o/--output", "existing folder"),
    (["import", "x.scxml", "-o", "{app}/graph.xml"], "-o/--output", "folder"),
])
def test_other_mistaken_arguments_are_one_line_and_exit_2(tmp_path, pause_app, capsys, argv,
                                                          argument, allowed):
    argv = [a.format(tmp=tmp_path, app=pause_app) for a in argv]
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert exit_.value.code == 2
    assert len(err) == 1 and f"argument {argument}" in err[0] and allowed in err[0], err


def test_an_address_the_emulator_cannot_listen_on_is_one_line(capsys):
    code = main(["emulate", "p2os", "--tcp", "1", "--host", "192.0.2.1"])   # TEST-NET: not ours
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "--tcp/--host" in err[0], err
