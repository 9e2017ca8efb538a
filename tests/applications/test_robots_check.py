"""`interbot robots --check PROFILE`: which of the devices a profile names answer."""
from __future__ import annotations

import time

import pytest

from applications.cli import main
from robots.clock import RealClock
from robots.link import PtyPair
from robots.lms2xx.emulator import LMS2xxEmulator
from robots.profile import PROFILE_DIR, load_profile
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")


def wired(tmp_path, device: str):
    path = tmp_path / "horos_wired.toml"
    path.write_text((PROFILE_DIR / "horos.toml").read_text().replace(
        "[laser]\n", f'[laser]\ndevice = "{device}"\n', 1))
    return str(path)


@pytest.fixture
def lms():
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    emulator = LMS2xxEmulator.for_profile(HOROS, simulation.world, clock=clock)
    emulator.attach(simulation)
    path = emulator.serve_pty()
    emulator.start_clock(simulation)
    yield emulator, path
    emulator.close()


def test_a_laser_that_answers(tmp_path, capsys, lms):
    emulator, path = lms
    assert main(["robots", "--check", wired(tmp_path, f"lms200:{path}")]) == 0
    out = capsys.readouterr().out
    assert out.startswith("laser ") and "answers: SICK LMS 200, 181 beams" in out
    deadline = time.monotonic() + 1.0               # opened, read, closed again
    while emulator.firmware.streaming and time.monotonic() < deadline:
        time.sleep(0.01)
    assert not emulator.firmware.streaming


def test_a_laser_that_does_not_answer(tmp_path, capsys):
    with PtyPair() as dead:
        code = main(["robots", "--check",
                     wired(tmp_path, f"lms200:{dead.path}?reply_timeout=0.05")])
    out = capsys.readouterr().out
    assert code == 1
    assert "NO ANSWER" in out and "no LMS 2xx answered" in out


def test_a_profile_without_devices(capsys):
    assert main(["robots", "--check", "horos"]) == 0
    assert "names no device at an address" in capsys.readouterr().out


def test_an_unknown_robot_is_a_usage_error(capsys):
    assert main(["robots", "--check", "nosuchbot"]) == 2
    assert "unknown robot 'nosuchbot'" in capsys.readouterr().err


def test_the_plain_listing_is_unchanged(capsys):
    assert main(["robots"]) == 0
    assert "horos" in capsys.readouterr().out
