"""On a real robot (a base at --port, the LMS its profile names) a laser that falls silent is
`robot.fault` for behaviors, and comes back by itself when the laser does: the whole chain from
the wire through L0, L1 and L2, over the emulators."""
from __future__ import annotations

import time

from behaviors.robot import open_robot
from robots.clock import RealClock
from robots.lms2xx.emulator import LMS2xxEmulator
from robots.p2os.emulator import P2OSEmulator
from robots.profile import PROFILE_DIR, load_profile
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")


def serve(cls):
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    emulator = cls.for_profile(HOROS, simulation.world, clock=clock)
    emulator.attach(simulation)
    path = emulator.serve_pty()
    emulator.start_clock(simulation)
    return emulator, path


def test_a_silent_laser_is_a_robot_fault_until_it_is_back(tmp_path):
    base, base_port = serve(P2OSEmulator)
    lms, lms_port = serve(LMS2xxEmulator)
    profile = tmp_path / "horos_wired.toml"
    profile.write_text((PROFILE_DIR / "horos.toml").read_text().replace(
        "[laser]\n", f'[laser]\ndevice = "lms200:{lms_port}?reply_timeout=0.3"\n', 1))
    robot = open_robot(profile, port=base_port)
    try:
        assert "laser" in robot.capabilities

        def fault_after(seconds: float, want: bool) -> bool:
            deadline = time.monotonic() + seconds
            while time.monotonic() < deadline:
                if robot.sense()["robot.fault"] is want:
                    return True
                time.sleep(0.1)
            return False
        assert fault_after(2.0, False)
        lms.muted = True
        assert fault_after(2.0, True)
        lms.muted = False
        assert fault_after(8.0, False)
        links = [e for e in robot.events() if e["kind"] == "link"]
        assert [(e["state"], e.get("device")) for e in links] == [("down", "laser"),
                                                                  ("up", "laser")]
        assert "laser link is down" in links[0]["reason"]
    finally:
        robot.close()
        lms.close()
        base.close()
