"""`interbot robots --check ROBOT`: one line per device saying whether it answers where the
profile (and --port) says it is; exit 0 when every named device answers, 1 when one does not."""
from __future__ import annotations

import cv2

from applications.cli import main
from robots.camera.intrinsics import Intrinsics
from robots.clock import RealClock
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
    assert out[1].startswith("head    answers at visca:") and "evi-d31 at address 1" in out[1]
    assert out[2].startswith("camera  answers at ") and "frames of 320 x 240 px" in out[2]


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
    assert out[1].startswith("head    DOES NOT ANSWER at visca:") and "AddressSet" in out[1]


def test_a_robot_naming_no_devices(capsys, tmp_path):
    profile = tmp_path / "nothing_here.toml"
    profile.write_text((PROFILE_DIR / "horos.toml").read_text())
    code = main(["robots", "--check", str(profile), "--port", str(tmp_path / "no-such-port")])
    out = capsys.readouterr().out.splitlines()
    assert code == 1                                  # the base does not answer
    assert out[0].startswith("base    DOES NOT ANSWER") and "cannot open" in out[0]
    assert out[1].startswith("head    not named") and out[2].startswith("camera  not named")


def test_an_unknown_robot_is_a_usage_error(capsys):
    assert main(["robots", "--check", "nosuchbot"]) == 2
    assert "unknown robot 'nosuchbot'" in capsys.readouterr().err
