"""A laser on a wire that goes down (silent, garbage, unplugged) makes `robot/link` false, so the
safety arbiter stops the robot and behaviors see `robot.fault`, with one `link` episode in the
trace whose reason names the laser; a simulated laser (always up) changes nothing."""
from __future__ import annotations

import time
from dataclasses import replace

import pytest

from robots.base import BaseState
from robots.clock import RealClock
from robots.devices import Laser
from robots.lms2xx.driver import LMS2xxLaser
from robots.lms2xx.emulator import LMS2xxEmulator
from robots.profile import load_profile
from robots.sim.simulation import Simulation
from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.localization import Localization


class StubBase:
    def __init__(self) -> None:
        self.state = BaseState(t=0.0, link_up=True)

    def read_state(self) -> BaseState:
        return self.state


class StubLaser(Laser):
    def __init__(self) -> None:
        self.link_up, self.link_error = True, ""

    def read(self):
        return None


def tick(localization, base, t):
    base.state = replace(base.state, t=t)
    localization.sense(t)


def test_a_laser_link_episode_is_a_robot_link_episode():
    base, laser, events, board = StubBase(), StubLaser(), EventLog(), Blackboard("test")
    localization = Localization(board, events, base, laser=laser)
    t = 0.0
    for _ in range(5):
        t += 0.1
        tick(localization, base, t)
    assert board.value("robot/link") is True
    laser.link_up, laser.link_error = False, "no reading for 0.40 s; the device is silent"
    for _ in range(10):
        t += 0.1
        tick(localization, base, t)
    assert board.value("robot/link") is False
    assert localization.status.failed and "laser link is down" in localization.status.reason
    laser.link_up, laser.link_error = True, ""
    for _ in range(3):
        t += 0.1
        tick(localization, base, t)
    assert board.value("robot/link") is True
    link = [e.as_dict() for e in events.drain() if e.kind == "link"]
    assert [e["state"] for e in link] == ["down", "up"]
    assert link[0]["reason"] == "laser link is down: no reading for 0.40 s; the device is silent"
    assert link[1]["after"] == pytest.approx(1.0, abs=0.15)


def test_a_laser_without_a_link_is_always_up():
    """Simulated and replayed lasers inherit link_up = True: runs do not change."""
    class Plain(Laser):
        def read(self):
            return None
    base, events, board = StubBase(), EventLog(), Blackboard("test")
    localization = Localization(board, events, base, laser=Plain())
    tick(localization, base, 0.1)
    assert board.value("robot/link") is True


def test_a_muted_lms_stops_the_robot_through_robot_link():
    profile = load_profile("horos")
    clock = RealClock()
    simulation = Simulation(profile, None, 0, clock)
    emulator = LMS2xxEmulator.for_profile(profile, simulation.world, clock=clock)
    emulator.attach(simulation)
    url = emulator.serve_pty()
    emulator.start_clock(simulation)
    laser = LMS2xxLaser.for_profile(profile, url, clock=clock, reply_timeout=0.3)
    base, events, board = StubBase(), EventLog(), Blackboard("test")
    localization = Localization(board, events, base, laser=laser)
    try:
        laser.open()
        assert laser.wait_for_reading(0, timeout=2.0)
        tick(localization, base, clock.now())
        assert board.value("robot/link") is True
        emulator.muted = True
        deadline = time.monotonic() + 2.0
        while board.value("robot/link") and time.monotonic() < deadline:
            time.sleep(0.05)
            tick(localization, base, clock.now())
        assert board.value("robot/link") is False
        down = [e.as_dict() for e in events.drain() if e.kind == "link"]
        assert down and "laser link is down" in down[0]["reason"]
        assert "silent" in down[0]["reason"]
    finally:
        laser.close()
        emulator.close()
