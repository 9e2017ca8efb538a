"""Every mistaken argument of every command is one line and exit 2, before anything is opened
(issue 24): a server port someone else holds, a file where a folder is meant, a folder that is
missing, a full disk, a file that is not what the command reads, a GoTo application on a real
base with no map. For `run`, the robot end at --port must never see a connection."""
from __future__ import annotations

import os
import socket
from pathlib import Path

import pytest

from applications.cli import main
from tests.faults.peer import ScriptedPioneer

FULL_DEVICE = Path("/dev/full")          # every write fails with ENOSPC: a full disk


@pytest.fixture(scope="module")
def robot_end():
    peer = ScriptedPioneer()
    yield peer
    peer.shutdown()


@pytest.fixture(scope="module")
def busy_port():
    """A port some other program listens on."""
    holder = socket.socket()
    holder.bind(("127.0.0.1", 0))
    holder.listen()
    yield holder.getsockname()[1]
    holder.close()


@pytest.fixture
def files(tmp_path):
    """{tmp}: a folder; {file}: a plain text file; {mcap}: an MCAP file that is no interbot
    recording; {mcap}: an MCAP file cut after its first bytes; {badline}: a trace with a broken second line; {html}: XML that is not SCXML."""
    (tmp_path / "notes.txt").write_text("not a recording\n")
    (tmp_path / "broken.jsonl").write_text('{"t": 0, "kind": "start"}\nnot json\n')
    (tmp_path / "page.scxml").write_text("<html/>\n")
    (tmp_path / "cut.mcap").write_bytes(b"\x89MCAP0\r\n" + b"\x01" * 3)   # cut after its magic
    return {"mcap": tmp_path / "cut.mcap", "tmp": tmp_path, "file": tmp_path / "notes.txt", "badline": tmp_path / "broken.jsonl",
            "html": tmp_path / "page.scxml"}


RUN_MISTAKES = [
    # (arguments after `run APP --port URL`, the argument named, words of the one line)
    (["--record", "{tmp}/missing/run.mcap"], "--record", "existing folder"),
    (["--record", "{tmp}"], "--record", "is a folder"),
    (["--inspect", "{busy}"], "--inspect", "Address already in use"),
    (["--inspect", "-3"], "--inspect", "outside 0 .. 65535"),
    (["--inspect", "host:1:2"], "--inspect", "unknown host"),
    (["--gui", "{busy}"], "--gui", "Address already in use"),
    (["--gui", "host:1:2"], "--gui", "unknown host"),
    (["--gui", "eighty"], "--gui", "no port number"),
    (["--foxglove", "{busy}"], "--foxglove", "Address already in use"),
    (["--speech-wav", "{file}"], "--speech-wav", "is a file"),
    (["--speech-wav", "{file}/deeper"], "--speech-wav", "cannot be created"),
    (["--language", "fr"], "--language", "texts are in English (en), German (de) only"),
    (["--language", "klingon"], "--language", "is not a language"),
]
if FULL_DEVICE.exists():
    RUN_MISTAKES.append((["--record", str(FULL_DEVICE)], "--record", "No space left"))


def one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    return err[0]


def exit_code(argv: list[str]) -> int:
    """main's exit code, whether argparse exits or main returns."""
    try:
        return main(argv)
    except SystemExit as exit_:
        return exit_.code


def fill(argv, files, busy):
    return [a.format(busy=busy, **files) for a in argv]


@pytest.mark.parametrize("extra,argument,words", RUN_MISTAKES)
def test_a_mistaken_run_argument_is_refused_before_the_robot_opens(
        robot_end, busy_port, files, capsys, extra, argument, words):
    before = robot_end.connections
    code = exit_code(["run", "survey", "--robot", "horos", "--port", robot_end.url,
                      *fill(extra, files, busy_port)])
    line = one_line(capsys)
    assert code == 2, line
    assert f"argument {argument}" in line and words in line, line
    assert robot_end.connections == before


def test_a_full_disk_is_refused_before_the_robot_opens(robot_end, files, capsys, monkeypatch):
    real = os.statvfs

    def full(path):
        stats = real(path)
        return os.statvfs_result((stats.f_bsize, stats.f_frsize, stats.f_blocks, 0, 0,
                                  stats.f_files, stats.f_ffree, stats.f_favail, stats.f_flag,
                                  stats.f_namemax))
    monkeypatch.setattr(os, "statvfs", full)
    before = robot_end.connections
    code = exit_code(["run", "survey", "--robot", "horos", "--port", robot_end.url,
                      "--record", str(files["tmp"] / "run.mcap")])
    line = one_line(capsys)
    assert code == 2 and "argument --record" in line and "no space left" in line, line
    assert robot_end.connections == before


def test_a_goto_application_on_a_real_base_without_a_map_is_refused(robot_end, capsys):
    before = robot_end.connections
    code = exit_code(["run", "guide", "--robot", "horos", "--port", robot_end.url])
    line = one_line(capsys)
    assert code == 2 and "argument --map" in line and "room_n1" in line, line
    assert robot_end.connections == before


def test_reset_faults_on_a_base_without_drive_faults_is_refused_before_the_robot_opens(
        robot_end, tmp_path, capsys):
    """--reset-faults is for the CAN, P2OS and rFLEX bases; a base without drive faults (the
    plain simulated one) refuses it before the port is touched."""
    horos = Path(__file__).resolve().parents[2] / "robots" / "profiles" / "horos.toml"
    robot = tmp_path / "simbot.toml"
    robot.write_text(horos.read_text().replace('driver = "p2os"', 'driver = "sim"'))
    before = robot_end.connections
    code = exit_code(["run", "survey", "--robot", str(robot), "--port", robot_end.url, "--reset-faults"])
    line = one_line(capsys)
    assert code == 2 and "--reset-faults" in line and "no drive faults to reset" in line, line
    assert robot_end.connections == before


OTHER_MISTAKES = [
    # (a whole command line, the argument named, words of the one line)
    (["replay", "{tmp}/missing.mcap"], "recording", "does not exist"),
    (["replay", "{tmp}"], "recording", "is a folder"),
    (["replay", "{file}"], "recording", "not an MCAP file"),
    (["replay", "{mcap}"], "recording", "cut.mcap"),
    (["replay", "{mcap}", "--speed", "0"], "--speed", "> 0"),
    (["replay", "{mcap}", "--inspect", "{busy}"], "--inspect", "Address already in use"),
    (["import", "{tmp}/missing.scxml", "-o", "{tmp}/app"], "scxml", "does not exist"),
    (["import", "{tmp}", "-o", "{tmp}/app"], "scxml", "is a folder"),
    (["import", "{html}", "-o", "{tmp}/app"], None, "not an SCXML document"),
    (["trace", "{tmp}/missing.jsonl"], "file", "does not exist"),
    (["trace", "{file}"], "file", "neither an MCAP recording nor a JSON-lines trace"),
    (["trace", "{badline}"], "file", "broken.jsonl:2"),
    (["trace", "{badline}", "--timeline", "{tmp}/states.gif"], "--timeline", "OUT.svg, OUT.png, OUT.pdf"),
    (["trace", "{badline}", "--path", "{tmp}/missing/path.svg"], "--path", "existing folder"),
    (["new", "{file}"], "folder", "is a file"),
    (["new", "{file}/app"], "folder", "cannot be created"),
    (["emulate", "p2os", "--tcp", "{busy}"], "--tcp/--host", "Address already in use"),
    (["emulate", "p2os", "--link", "{tmp}/missing/pty"], "--link", "existing folder"),
    (["emulate", "p2os", "--scenario", "{tmp}/missing.toml"], None, "no such scenario file"),
]


@pytest.mark.parametrize("argv,argument,words", OTHER_MISTAKES)
def test_a_mistaken_argument_of_another_command_is_one_line_and_exit_2(
        busy_port, files, capsys, argv, argument, words):
    code = exit_code(fill(argv, files, busy_port))
    line = one_line(capsys)
    assert code == 2, line
    assert words in line, line
    if argument is not None:
        assert f"argument {argument}" in line, line
    assert not (files["tmp"] / "app").exists()       # import wrote nothing
