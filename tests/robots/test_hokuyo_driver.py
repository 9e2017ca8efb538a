"""The SCIP 2.0 driver against its emulator over a pty (URG-04LX) and TCP (UST-10LX), and
each link fault."""
from __future__ import annotations

import math
import time

import numpy as np
import pytest
import serial

from robots.clock import RealClock
from robots.exceptions import CommandError, HandshakeError
from robots.hokuyo import protocol as p
from robots.hokuyo.driver import HokuyoLaser
from robots.hokuyo.emulator import HokuyoEmulator
from robots.link import PtyPair
from robots.profile import load_profile
from robots.sim.rangefinder import WorldRangefinder
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")        # 180 deg laser: a URG-04LX
ARGOS = load_profile("argos")        # 270 deg laser: a UST-10LX


def wait_until(predicate, timeout=3.0, step=0.01):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(step)
    return predicate()


class FaultyHokuyo(HokuyoEmulator):
    """The emulator with a fault switch for its stream: "check" spoils a data line's check
    character, "noise" sends bytes that form no reply."""
    fault: str | None = None

    def _send(self, data: bytes) -> None:
        if self.fault == "check" and b"\n99b\n" in data:
            lines = data.split(b"\n")
            lines[3] = lines[3][:-1] + bytes([0x30 + (lines[3][-1] - 0x30 + 1) % 64])
            data = b"\n".join(lines)
        elif self.fault == "noise" and b"\n99b\n" in data:
            data = bytes(0x80 | b for b in data)
        super()._send(data)


def start(profile, cls=HokuyoEmulator, tcp=False, link=None):
    clock = RealClock()
    simulation = Simulation(profile, None, 0, clock)
    emulator = cls.for_profile(profile, simulation.world, clock=clock)
    emulator.attach(simulation)
    if tcp:
        host, port = emulator.serve_tcp()
        url = f"socket://{host}:{port}"
    else:
        url = emulator.serve_pty(link=link)
    emulator.start_clock(simulation)
    return emulator, url, simulation, clock


@pytest.fixture
def urg(tmp_path):
    emulator, url, simulation, clock = start(HOROS, FaultyHokuyo, link=str(tmp_path / "ttyACM"))
    laser = HokuyoLaser.for_profile(HOROS, url, clock=clock, reply_timeout=0.3)
    yield laser, emulator, url, simulation
    laser.close()
    emulator.close()


def test_handshake_and_scans_over_a_pty(urg):
    laser, emulator, _, simulation = urg
    laser.open()
    assert laser.version["PROT"] == "SCIP 2.0"
    assert laser.params["AMIN"] == 44 and laser.params["AMAX"] == 725
    assert emulator.firmware.laser and emulator.firmware.stream is not None
    assert laser.wait_for_reading(0, timeout=2.0)
    scan = laser.read()
    assert len(scan.ranges) == 682
    # step 384 looks ahead; steps are 360/1024 deg apart
    assert scan.angles[384 - 44] == pytest.approx(0.0)
    assert scan.angles[1] - scan.angles[0] == pytest.approx(2 * math.pi / 1024)
    finder = WorldRangefinder.for_profile(HOROS, simulation.world)
    finder.noise = 0.0
    truth = finder.cast(scan.angles)
    truth[truth > 5.6] = np.inf                       # beyond the URG-04LX's DMAX
    both = np.isfinite(truth) & np.isfinite(scan.ranges)
    assert both.sum() > 300
    assert np.abs(scan.ranges[both] - truth[both]).max() < 0.06


def test_scans_come_at_the_rotation_speed(urg):
    laser, _, _, _ = urg
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    start_count = laser.stats["readings"]
    time.sleep(1.0)
    assert 8 <= laser.stats["readings"] - start_count <= 11     # 600 rpm: 10 scans a second


def test_tcp_ust_with_clusters():
    emulator, url, _, clock = start(ARGOS, tcp=True)
    laser = HokuyoLaser.for_profile(ARGOS, url, clock=clock, cluster=3, reply_timeout=0.3)
    try:
        laser.open()
        assert laser.params["ARES"] == 1440 and laser.params["SCAN"] == 2400
        assert laser.wait_for_reading(0, timeout=2.0)
        scan = laser.read()
        assert len(scan.ranges) == 361          # 1081 steps in clusters of 3 (the last of 1)
        assert np.degrees(scan.angles[[0, -1]]).tolist() == pytest.approx([-134.75, 135.0])
        start_count = laser.stats["readings"]
        time.sleep(1.0)
        assert 30 <= laser.stats["readings"] - start_count <= 42   # 2400 rpm: 40 a second
    finally:
        laser.close()
        emulator.close()


def test_emulator_answers_errors_with_status_codes(urg):
    _, emulator, url, _ = urg
    port = serial.serial_for_url(url, timeout=0.5)
    parser = p.ScipParser()

    def ask(line: bytes) -> p.Reply:
        port.write(line)
        deadline = time.monotonic() + 1.0
        while time.monotonic() < deadline:
            for reply in parser.feed(port.read(max(1, port.in_waiting))):
                if reply.status != p.STATUS_STREAM:
                    return reply
        raise AssertionError(f"no reply to {line!r}")
    try:
        assert ask(b"GD0044072501\n").status == "10"         # laser off
        assert ask(b"BM\n").status == "00"
        assert ask(b"BM\n").status == "02"                   # already on
        assert ask(b"GD0044072501\n").status == "00"
        assert ask(b"GD0044000001\n").status == "04"         # end step below AMIN
        assert ask(b"GD0100005001\n").status == "05"         # end before start
        assert ask(b"GDxx44072501\n").status == "01"
        assert ask(b"XX\n").status == p.STATUS_UNKNOWN_COMMAND
        assert ask(b"MD0044072501102;two\n").status == "00"  # 2 scans, every other one
        deadline = time.monotonic() + 2.0
        scans = []
        while len(scans) < 2 and time.monotonic() < deadline:
            scans += [r for r in parser.feed(port.read(max(1, port.in_waiting)))
                      if r.status == p.STATUS_STREAM]
        assert [s.echo for s in scans] == ["MD0044072501101;two", "MD0044072501100;two"]
        assert emulator.firmware.stream is None              # the order is done
    finally:
        port.close()


def test_nothing_answering_is_a_handshake_error():
    with PtyPair() as pty:
        laser = HokuyoLaser(pty.path, reply_timeout=0.05, reconnect=False)
        with pytest.raises(HandshakeError, match="no reply to QT"):   # after SCIP2.0
            laser.open()
        laser.close()


def test_a_sensor_not_speaking_scip2_is_refused(tmp_path):
    class Old(HokuyoEmulator):
        def receive(self, data):
            if data.startswith(b"VV"):
                self._send(p.reply("VV", "00", p.info_lines({"PROT": "SCIP 1.1"}), info=True))
                return
            super().receive(data)
    emulator, url, _, clock = start(HOROS, Old)
    laser = HokuyoLaser(url, reply_timeout=0.3, reconnect=False)
    try:
        with pytest.raises(HandshakeError, match="speaks 'SCIP 1.1', not SCIP 2.0, and did "
                                                 "not switch"):
            laser.open()
    finally:
        laser.close()
        emulator.close()


def test_options_out_of_range_are_refused():
    with pytest.raises(CommandError, match="cluster count 0: allowed 1..99"):
        HokuyoLaser("/dev/null", cluster=0)


# -- faults -----------------------------------------------------------------------------------------
def test_silence_is_a_link_fault_and_the_laser_comes_back(urg):
    laser, emulator, _, _ = urg
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.muted = True
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    assert laser.read() is None and "the device is silent" in laser.link_error
    emulator.muted = False
    assert wait_until(lambda: laser.link_up and laser.read() is not None, timeout=8.0)
    assert laser.stats["reconnects"] == 1


def test_garbage_is_a_link_fault_with_its_reason(urg):
    laser, emulator, _, _ = urg
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.fault = "noise"
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    assert "bytes formed no reply" in laser.link_error and laser.read() is None


def test_bad_check_character_is_a_link_fault_naming_the_byte_offset(urg):
    laser, emulator, _, _ = urg
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.fault = "check"
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    # the first data line (line 4) of each scan carries a wrong check character
    assert "line 4 check character" in laser.link_error
    offset = int(laser.link_error.split("last: byte ")[1].split(":")[0])
    assert offset > 0 and laser.parser.stats.bad_checksum >= 1


def test_unplugged_is_a_link_fault_and_replugging_brings_it_back(urg):
    laser, emulator, url, _ = urg
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.unplug()
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    assert laser.read() is None
    emulator.serve_pty(link=url)
    assert wait_until(lambda: laser.link_up and laser.read() is not None, timeout=8.0)


def test_close_stops_the_stream(urg):
    laser, emulator, _, _ = urg
    laser.open()
    laser.close()
    assert wait_until(lambda: emulator.firmware.stream is None and not emulator.firmware.laser,
                      timeout=1.0)


def test_a_dropped_tcp_connection_is_a_link_fault_and_the_driver_connects_again():
    emulator, url, _, clock = start(ARGOS, tcp=True)
    laser = HokuyoLaser.for_profile(ARGOS, url, clock=clock, reply_timeout=0.3)
    try:
        laser.open()
        assert laser.wait_for_reading(0, timeout=2.0)
        emulator.unplug()                        # the switch port goes dark
        assert wait_until(lambda: not laser.link_up, timeout=2.0)
        assert laser.read() is None
        assert wait_until(lambda: laser.link_up and laser.read() is not None, timeout=8.0)
        assert emulator.connections == 2 and laser.stats["reconnects"] == 1
    finally:
        laser.close()
        emulator.close()


def test_an_old_urg_is_switched_to_scip2_first():
    class OldFirmware(HokuyoEmulator):
        switched = False

        def receive(self, data):
            if data.startswith(b"SCIP2.0"):
                self.switched = True
                self._send(b"SCIP2.0\n0\n\n")      # the SCIP 1.1 answer: status 0, no check
                return
            super().receive(data)
    emulator, url, _, clock = start(HOROS, OldFirmware)
    laser = HokuyoLaser(url, reply_timeout=1.0, reconnect=False)
    try:
        began = time.monotonic()
        laser.open()
        assert emulator.switched and emulator.received[0] == "QT"
        assert time.monotonic() - began < 0.8              # did not wait out the timeout
        assert laser.wait_for_reading(0, timeout=2.0)
    finally:
        laser.close()
        emulator.close()
