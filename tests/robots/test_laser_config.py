"""A profile's [laser] device: checked when the profile loads, opened beside the base on a real
robot (`open_hardware(..., port=...)`), left alone in simulation."""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest

from robots.clock import RealClock
from robots.exceptions import HandshakeError, LinkError, ProfileError
from robots.hardware import open_hardware
from robots.hokuyo.driver import HokuyoLaser
from robots.hokuyo.emulator import HokuyoEmulator
from robots.lasers import parse_laser_device
from robots.link import PtyPair
from robots.lms2xx.driver import LMS2xxLaser
from robots.lms2xx.emulator import LMS2xxEmulator
from robots.p2os.emulator import P2OSEmulator
from robots.profile import PROFILE_DIR, load_profile
from robots.sim.devices import SimLaser
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")


def profile_with_device(tmp_path: Path, device: str, robot: str = "horos") -> Path:
    """A copy of a bundled profile whose [laser] names `device`."""
    text = (PROFILE_DIR / f"{robot}.toml").read_text()
    path = tmp_path / f"{robot}_wired.toml"
    path.write_text(text.replace("[laser]\n", f"[laser]\ndevice = {device!r}\n", 1)
                    .replace("'", '"'))
    return path


# -- the address --------------------------------------------------------------------------------------
def test_device_addresses():
    a = parse_laser_device("lms200:/dev/ttyUSB0?baud=38400&resolution=0.5&units=cm")
    assert (a.kind, a.url, a.options) == ("lms200", "/dev/ttyUSB0",
                                          {"baud": 38400, "resolution": 0.5, "units": "cm"})
    a = parse_laser_device("ust:socket://192.168.0.10:10940?cluster=2")
    assert (a.kind, a.url, a.options) == ("ust", "socket://192.168.0.10:10940", {"cluster": 2})


@pytest.mark.parametrize("text,message", [
    ("sick:/dev/ttyUSB0", "kind 'sick' is not a laser we drive; allowed: lms200, lms291, urg, ust"),
    ("/dev/ttyUSB0", "is not a laser we drive"),
    ("lms200:", "no address after 'lms200:'"),
    ("lms200:/dev/ttyS0?speed=9600", "option 'speed' is not one of lms200's: baud, angle"),
    ("lms200:/dev/ttyS0?baud=fast", "option baud='fast' must be a whole number"),
])
def test_bad_device_addresses_say_what_is_allowed(text, message):
    with pytest.raises(ValueError, match=message):
        parse_laser_device(text)


def test_profile_checks_its_device_when_loaded(tmp_path):
    good = load_profile(profile_with_device(tmp_path, "lms200:/dev/ttyUSB0?baud=38400"))
    assert good.laser.device == "lms200:/dev/ttyUSB0?baud=38400"
    assert load_profile("horos").laser.device is None
    bad = profile_with_device(tmp_path, "lms200:/dev/ttyUSB0?baud=lots")
    with pytest.raises(ProfileError, match=r"horos_wired.toml:\d+: \[laser\] device = .*baud"):
        load_profile(bad)


# -- opening -------------------------------------------------------------------------------------------
@pytest.fixture
def base_emulator():
    """A P2OS controller to be the real robot's base."""
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    emulator.attach(simulation)
    path = emulator.serve_pty()
    emulator.start_clock(simulation)
    yield path, emulator
    emulator.close()


def laser_emulator(cls, profile, tcp=False):
    clock = RealClock()
    simulation = Simulation(profile, None, 0, clock)
    emulator = cls.for_profile(profile, simulation.world, clock=clock)
    emulator.attach(simulation)
    url = "socket://{}:{}".format(*emulator.serve_tcp()) if tcp else emulator.serve_pty()
    emulator.start_clock(simulation)
    return emulator, url


def test_a_real_robot_opens_its_lms_beside_the_base(tmp_path, base_emulator):
    base_port, _ = base_emulator
    lms, url = laser_emulator(LMS2xxEmulator, HOROS)
    try:
        profile = profile_with_device(tmp_path, f"lms200:{url}?baud=38400")
        hardware = open_hardware(profile, port=base_port)
        try:
            assert isinstance(hardware.laser, LMS2xxLaser)
            assert "laser" in hardware.capabilities
            assert hardware.laser.wait_for_reading(0, timeout=2.0)
            assert len(hardware.laser.read().ranges) == 181
            assert lms.firmware.streaming and lms.firmware.baud == 38400
        finally:
            hardware.close()
        deadline = time.monotonic() + 1.0
        while lms.firmware.streaming and time.monotonic() < deadline:
            time.sleep(0.01)
        assert not lms.firmware.streaming           # closing the robot closed the laser
    finally:
        lms.close()


def test_a_real_robot_with_a_hokuyo_on_tcp(tmp_path, base_emulator):
    base_port, _ = base_emulator
    urg, url = laser_emulator(HokuyoEmulator, HOROS, tcp=True)
    try:
        hardware = open_hardware(profile_with_device(tmp_path, f"urg:{url}"), port=base_port)
        try:
            assert isinstance(hardware.laser, HokuyoLaser)
            assert hardware.laser.wait_for_reading(0, timeout=2.0)
        finally:
            hardware.close()
    finally:
        urg.close()


def test_a_laser_that_does_not_answer_stops_the_start_and_closes_the_base(tmp_path,
                                                                           base_emulator):
    base_port, base = base_emulator
    with PtyPair() as dead:
        profile = profile_with_device(tmp_path, f"lms200:{dead.path}?reply_timeout=0.05")
        with pytest.raises(HandshakeError, match=r"laser lms200 \(\[laser\] device of horos\)"):
            open_hardware(profile, port=base_port)
    deadline = time.monotonic() + 1.0
    while base.firmware.open and time.monotonic() < deadline:
        time.sleep(0.01)
    assert not base.firmware.open                   # the base was closed again


def test_simulation_keeps_its_in_process_laser(tmp_path):
    hardware = open_hardware(profile_with_device(tmp_path, "lms200:/dev/nonexistent"),
                             fast=True)
    try:
        assert isinstance(hardware.laser, SimLaser)
    finally:
        hardware.close()


# -- the laser on its wire in simulation ("KIND:sim") -------------------------------------------------
def run_ticks(hardware, ticks: int) -> list:
    scans = []
    for _ in range(ticks):
        hardware.sense()
        scans.append(hardware.laser.read())
        hardware.clock.advance(0.1)
    return scans


@pytest.mark.parametrize("kind, driver", [("lms200", LMS2xxLaser), ("urg", HokuyoLaser)])
def test_sim_address_puts_the_laser_on_its_wire_deterministically(tmp_path, kind, driver):
    profile = profile_with_device(tmp_path, f"{kind}:sim")
    runs = []
    for _ in range(2):
        hardware = open_hardware(profile, fast=True)
        try:
            assert isinstance(hardware.laser, driver) and hardware.laser.lockstep is not None
            runs.append(run_ticks(hardware, 20))
        finally:
            hardware.close()
    first, second = runs
    assert sum(scan is not None for scan in first) >= 18       # a scan about every tick
    for a, b in zip(first, second):                             # lock-step: the same run twice
        assert (a is None) == (b is None)
        if a is not None:
            assert a.t == b.t and np.array_equal(a.ranges, b.ranges)


def test_the_wire_laser_sees_what_the_simulated_laser_sees(tmp_path):
    wired = open_hardware(profile_with_device(tmp_path, "lms200:sim"), fast=True)
    plain = open_hardware("horos", fast=True)
    try:
        scan = run_ticks(wired, 3)[-1]
        run_ticks(plain, 3)
        reference = plain.laser.read()
        assert np.allclose(scan.angles, reference.angles)
        both = np.isfinite(scan.ranges) & np.isfinite(reference.ranges)
        assert both.sum() > 150
        assert np.abs(scan.ranges[both] - reference.ranges[both]).max() < 0.08   # 1 cm noise each
    finally:
        wired.close()
        plain.close()


def test_a_silent_wire_laser_in_lockstep_is_a_link_fault_in_sim_time(tmp_path):
    hardware = open_hardware(profile_with_device(tmp_path, "lms200:sim"), fast=True)
    try:
        run_ticks(hardware, 3)
        hardware.laser.emulator.muted = True
        scans = run_ticks(hardware, 6)                   # 0.6 s of sim time, no wall waiting
        assert not hardware.laser.link_up and scans[-1] is None
        assert "the device is silent" in hardware.laser.link_error
    finally:
        hardware.close()


def test_the_sim_address_is_refused_on_a_real_robot(tmp_path, base_emulator):
    base_port, _ = base_emulator
    with pytest.raises(LinkError, match="'sim' is the simulated world's emulator"):
        open_hardware(profile_with_device(tmp_path, "lms200:sim"), port=base_port)
