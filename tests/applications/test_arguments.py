"""Mistaken arguments: one line naming the argument, what is wrong and what is allowed, exit 2,
before the robot is opened (the robot end at --port never sees a connection)."""
from __future__ import annotations

import math

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
    (["--map", "{app}/graph.xml"], "--map", "a map_server .yaml"),
    (["--map", "{tmp}"], "--map", "a floor .toml"),
    (["--map", "{tmp}/floor3.yaml"], "--map", "bundled floor name"),
    (["--map", ""], "--map", "bundled floor name"),
    (["--map", "office", "--initial-pose", "1,2"], "--initial-pose", "X,Y,HEADING_DEG"),
    (["--map", "office", "--initial-pose", "1,2,north"], "--initial-pose", "X,Y,HEADING_DEG"),
    (["--map", "office", "--initial-pose", "1,nan,0"], "--initial-pose", "X,Y,HEADING_DEG"),
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
    (["import", "{app}/graph.xml", "-o", "{app}/graph.xml"], "-o/--output", "folder"),
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


BAD_MAP = "image: floor3.pgm\nresolution: fine\norigin: [0.0, 0.0, 0.0]\n"


def write_half_known_map(folder):
    """A 4 m × 4 m map_server map, 0.1 m cells: the west half unknown, the east half free."""
    pixels = bytes(([205] * 20 + [254] * 20) * 40)
    (folder / "half.pgm").write_bytes(b"P5\n40 40\n255\n" + pixels)
    (folder / "half.yaml").write_text("image: half.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\n"
                                      "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")


@pytest.mark.parametrize("extra,words", [
    (["--map", "{tmp}/floor3.yaml"], ["floor3.yaml", "resolution"]),        # the file, the field
    (["--map", "atlantis"], ["unknown floor 'atlantis'", "office"]),
    (["--map", "office", "--initial-pose=40,0,0"], ["off the map 'office'", "allowed x"]),
    (["--map", "{tmp}/half.yaml", "--initial-pose", "0.3,2,0"],
     ["m inside unknown space of the map 'half'", "within 1 m"]),
])
def test_a_map_or_start_pose_that_does_not_fit_is_one_line_before_the_robot_opens(
        robot_end, pause_app, tmp_path, capsys, extra, words):
    (tmp_path / "floor3.yaml").write_text(BAD_MAP)
    write_half_known_map(tmp_path)
    extra = [a.format(tmp=tmp_path) for a in extra]
    before = robot_end.connections
    code = main(["run", str(pause_app), "--port", robot_end.url, *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert all(word in err[0] for word in words), err
    assert robot_end.connections == before


def test_a_start_pose_without_a_map_on_a_real_base_is_refused(robot_end, pause_app, capsys):
    before = robot_end.connections
    code = main(["run", str(pause_app), "--port", robot_end.url, "--initial-pose", "0,0,90"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "argument --initial-pose" in err[0]
    assert "--map" in err[0]
    assert robot_end.connections == before


def test_map_and_start_pose_reach_localization(pause_app, tmp_path, monkeypatch, capsys):
    import behaviors.robot
    opened = []
    real = behaviors.robot.open_robot

    def spy(*args, **kwargs):
        robot = real(*args, **kwargs)
        opened.append(robot.skills)
        return robot
    monkeypatch.setattr(behaviors.robot, "open_robot", spy)
    code = main(["run", str(pause_app), "--fast", "--duration", "0.3", "--quiet",
                 "--data", str(tmp_path), "--map", "office", "--initial-pose=-2.5,0.5,-90"])
    assert code == 0, capsys.readouterr().err
    skills = opened[0]
    assert skills.map.name == "office"
    assert skills.localization.initial_pose == pytest.approx((-2.5, 0.5, -math.pi / 2))
