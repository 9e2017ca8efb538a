"""`interbot robots --check ROBOT`: one line per device saying whether it answers where the
profile (and --port) says it is; exit 0 when every named device answers, 1 when one does not."""
from __future__ import annotations

import time

import cv2
import pytest

from applications.cli import main
from robots.camera.intrinsics import Intrinsics
from robots.clock import RealClock
from robots.link import PtyPair
from robots.lms2xx.emulator import LMS2xxEmulator
from robots.p2os.emulator import P2OSEmulator
from robots.profile import PROFILE_DIR, load_profile
from robots.sim.simulation import Simulation
from robots.visca.emulator import ViscaEmulator
from tests.robots.camera_scenes import blank

HOROS = load_profile("horos")


def setup_robot(tmp_path):
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    base = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    base.attach(simulation)
    base_url = base.serve_pty()
    base.start_clock(simulation)
    head = ViscaEmulator.for_profile(HOROS)
    head.start_clock()
    video = str(tmp_path / "empty.avi")
    writer = cv2.VideoWriter(video, cv2.VideoWriter_fourcc(*"MJPG"), 10.0, (320, 240))
    for _ in range(5):
        writer.write(blank(Intrinsics.from_fov(60.0, 320, 240)))
    writer.release()
    text = (PROFILE_DIR / "horos.toml").read_text()
    text = text.replace("[head]\n", f'[head]\ndevice = "visca:{head.serve_pty()}"\n', 1)
    text += f'\n[camera]\ndevice = "{video}"\n'
    profile = tmp_path / "horos_here.toml"
    profile.write_text(text)
    return profile, base_url, base, head


def test_every_device_answers(tmp_path, capsys):
    profile, base_url, base, head = setup_robot(tmp_path)
    try:
        code = main(["robots", "--check", str(profile), "--port", base_url])
    finally:
        head.close()
        base.close()
    out = capsys.readouterr().out.splitlines()
    assert code == 0, out
    assert out[0].startswith(f"base    answers at {base_url}: p2os base horos Pioneer p2dx")
    assert out[1].startswith("laser   not named")        # a laser on the wire: tests below
    assert out[2].startswith("head    answers at visca:") and "evi-d31 at address 1" in out[2]
    assert out[3].startswith("camera  answers at ") and "frames of 320 x 240 px" in out[3]


def test_a_silent_head_is_named(tmp_path, capsys):
    profile, base_url, base, head = setup_robot(tmp_path)
    head.muted = True
    try:
        code = main(["robots", "--check", str(profile), "--port", base_url])
    finally:
        head.close()
        base.close()
    out = capsys.readouterr().out.splitlines()
    assert code == 1
    assert out[0].startswith("base    answers")
    assert out[2].startswith("head    DOES NOT ANSWER at visca:") and "AddressSet" in out[2]


def test_a_robot_naming_no_devices(capsys, tmp_path):
    profile = tmp_path / "nothing_here.toml"
    profile.write_text((PROFILE_DIR / "horos.toml").read_text())
    code = main(["robots", "--check", str(profile), "--port", str(tmp_path / "no-such-port")])
    out = capsys.readouterr().out.splitlines()
    assert code == 1                                  # the base does not answer
    assert out[0].startswith("base    DOES NOT ANSWER") and "cannot open" in out[0]
    assert [line.split(":")[0].split() for line in out[1:]] == [["laser", "not", "named"],
                                                                 ["head", "not", "named"],
                                                                 ["camera", "not", "named"]]


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
    code = main(["robots", "--check", wired(tmp_path, f"lms200:{path}"),
                 "--port", str(tmp_path / "no-base-here")])
    out = capsys.readouterr().out.splitlines()
    assert code == 1 and out[0].startswith("base    DOES NOT ANSWER")     # no base in this test
    assert out[1].startswith(f"laser   answers at lms200:{path}: SICK LMS 200, 181 beams")
    deadline = time.monotonic() + 1.0               # opened, read, closed again
    while emulator.firmware.streaming and time.monotonic() < deadline:
        time.sleep(0.01)
    assert not emulator.firmware.streaming


def test_a_laser_that_does_not_answer(tmp_path, capsys):
    with PtyPair() as dead:
        code = main(["robots", "--check",
                     wired(tmp_path, f"lms200:{dead.path}?reply_timeout=0.05"),
                     "--port", str(tmp_path / "no-base-here")])
    out = capsys.readouterr().out.splitlines()
    assert code == 1
    assert out[1].startswith("laser   DOES NOT ANSWER") and "no LMS 2xx answered" in out[1]


def test_an_unknown_robot_is_a_usage_error(capsys):
    assert main(["robots", "--check", "nosuchbot"]) == 2
    assert "unknown robot 'nosuchbot'" in capsys.readouterr().err


def test_the_plain_listing_is_unchanged(capsys):
    assert main(["robots"]) == 0
    assert "horos" in capsys.readouterr().out
