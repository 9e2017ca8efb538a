"""`interbot run --port URL --laser ADDRESS --head ADDRESS`: each device's address from the
command line, over the profile's (issue 26). Here the devices are their emulators started by
hand, as a lab without the hardware would (`interbot emulate p2os|lms200|visca --tcp 0`); the
profile names ports that do not exist, so a run that opens only because the command line
named the right ones shows the command line won. A mistaken address is one line and exit 2
before the base at --port is opened."""
from __future__ import annotations

import re
import subprocess
import sys

import pytest

import behaviors.robot
from applications.cli import main
from robots.lms2xx.driver import LMS2xxLaser
from robots.profile import PROFILE_DIR
from robots.visca.driver import ViscaHead
from tests.applications.test_real_port import BASE_ONLY_APP
from tests.faults.peer import ScriptedPioneer


def start_emulator(name: str) -> tuple[subprocess.Popen, str]:
    proc = subprocess.Popen([sys.executable, "-m", "applications.cli", "emulate", name,
                             "--tcp", "0"], stdout=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    match = re.search(r"connect to: (\S+)", line)
    assert match, line
    return proc, match.group(1)


@pytest.fixture
def emulators():
    started = {name: start_emulator(name) for name in ("p2os", "lms200", "visca")}
    try:
        yield {name: url for name, (_, url) in started.items()}
    finally:
        for proc, _ in started.values():
            proc.terminate()
            proc.wait(timeout=10)


@pytest.fixture
def stale_profile(tmp_path):
    """HOROS with its laser and head named at ports this machine does not have."""
    path = tmp_path / "horos_moved.toml"
    path.write_text((PROFILE_DIR / "horos.toml").read_text()
                    .replace("[laser]\n", '[laser]\ndevice = "lms200:/dev/ttyUSB7"\n', 1)
                    .replace("[head]\n", '[head]\ndevice = "visca:/dev/ttyUSB8"\n', 1))
    return path


@pytest.fixture
def pause_app(tmp_path):
    app = tmp_path / "pause"
    app.mkdir()
    (app / "graph.xml").write_text(BASE_ONLY_APP)
    return app


def test_the_command_line_names_where_the_laser_and_head_are(
        tmp_path, capsys, monkeypatch, emulators, stale_profile, pause_app):
    opened = []
    real_open = behaviors.robot.open_robot

    def spy(*args, **kwargs):
        robot = real_open(*args, **kwargs)
        hardware = robot.skills.hardware
        opened.append((hardware.laser, hardware.head))
        return robot
    monkeypatch.setattr(behaviors.robot, "open_robot", spy)
    code = main(["run", str(pause_app), "--robot", str(stale_profile),
                 "--port", emulators["p2os"], "--laser", f"lms200:{emulators['lms200']}",
                 "--head", f"visca:{emulators['visca']}", "--duration", "2",
                 "--data", str(tmp_path), "--quiet"])
    assert code == 0, capsys.readouterr().err
    laser, head = opened[0]
    assert isinstance(laser, LMS2xxLaser) and isinstance(head, ViscaHead)
    assert laser.stats["readings"] > 5 and laser.stats["link_downs"] == 0   # it read scans
    assert laser.url == emulators["lms200"] and head.url == emulators["visca"]


@pytest.fixture(scope="module")
def robot_end():
    peer = ScriptedPioneer()
    yield peer
    peer.shutdown()


@pytest.mark.parametrize("extra, words", [
    (["--laser", "sick:/dev/ttyUSB0"], "argument --laser 'sick:/dev/ttyUSB0': kind 'sick'"),
    (["--laser", "lms200:/dev/ttyUSB0?baud=fast"], "baud='fast' must be a whole number"),
    (["--head", "pelco:/dev/ttyUSB1"], "DRIVER one of visca"),
    (["--camera", "/dev/video0"], "robot 'horos' has no [camera]"),
    (["--wire"], "argument --wire"),
])
def test_a_mistaken_device_address_is_refused_before_the_base_opens(
        robot_end, pause_app, capsys, extra, words):
    before = robot_end.connections
    code = main(["run", str(pause_app), "--robot", "horos", "--port", robot_end.url, *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and words in err[0], err
    assert robot_end.connections == before


def test_in_simulation_a_laser_port_is_refused_and_its_emulator_named(pause_app, capsys):
    code = main(["run", str(pause_app), "--robot", "horos", "--fast", "--laser",
                 "lms200:/dev/ttyUSB0"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "'lms200:sim'" in err[0], err
