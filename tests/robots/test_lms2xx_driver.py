"""The LMS 2xx driver against its emulator over a pty and over TCP, and each link fault."""
from __future__ import annotations

import math
import time

import numpy as np
import pytest
import serial

from robots.clock import RealClock
from robots.exceptions import CommandError, HandshakeError
from robots.link import PtyPair
from robots.lms2xx import protocol as p
from robots.lms2xx.driver import LMS2xxLaser
from robots.lms2xx.emulator import LMS2xxEmulator
from robots.profile import load_profile
from robots.sim.rangefinder import WorldRangefinder
from robots.sim.simulation import Simulation
from tests.waiting import wait_until

HOROS = load_profile("horos")


class FaultyLMS(LMS2xxEmulator):
    """The emulator with a fault switch for its stream: "crc" flips a CRC byte of every scan,
    "noise" sends bytes that form no telegram instead."""
    fault: str | None = None

    def _send_scan(self):
        if self.fault is None:
            return super()._send_scan()
        telegram = bytearray(p.measured_values_reply(self._values(), self.firmware.units))
        if self.fault == "crc":
            telegram[-1] ^= 0x5A
            self._send(bytes(telegram))
        else:
            self._send(bytes(0xF0 | (b & 0x0F) for b in telegram))


@pytest.fixture
def world():
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    return clock, simulation


def start_emulator(world, cls=LMS2xxEmulator, tcp=False, link=None):
    clock, simulation = world
    emulator = cls.for_profile(HOROS, simulation.world, clock=clock)
    emulator.attach(simulation)
    if tcp:
        host, port = emulator.serve_tcp()
        url = f"socket://{host}:{port}"
    else:
        url = emulator.serve_pty(link=link)
    emulator.start_clock(simulation)
    return emulator, url


@pytest.fixture
def on_pty(world, tmp_path):
    emulator, url = start_emulator(world, FaultyLMS, link=str(tmp_path / "ttyLMS"))
    laser = LMS2xxLaser.for_profile(HOROS, url, clock=world[0], reply_timeout=0.3)
    yield laser, emulator, url
    laser.close()
    emulator.close()


def expected_ranges(simulation, laser_angles):
    """The noise-free ranges the world gives along the driver's beams."""
    finder = WorldRangefinder.for_profile(HOROS, simulation.world)
    finder.noise = 0.0
    return finder.cast(np.asarray(laser_angles) - HOROS.laser.heading)


def test_profile_mode_and_handshake_over_a_pty(on_pty, world):
    laser, emulator, _ = on_pty
    assert (laser.angle, laser.resolution) == (180, 100)    # HOROS: 180 deg, 181 beams
    laser.open()
    fw = emulator.firmware
    assert laser.found_baud == 9600                          # the LMS's power-up speed
    assert fw.baud == 38400 and fw.streaming and fw.units == "mm"
    assert (fw.angle, fw.resolution) == (180, 100)
    assert laser.wait_for_reading(0, timeout=2.0)
    scan = laser.read()
    assert len(scan.angles) == 181 and scan.origin == (HOROS.laser.x, 0.0, 0.0)
    assert scan.angles[0] == pytest.approx(-math.pi / 2) and scan.angles[-1] == pytest.approx(math.pi / 2)
    truth = expected_ranges(world[1], scan.angles)
    hit = np.isfinite(truth) & np.isfinite(scan.ranges)
    assert hit.sum() > 100
    assert np.abs(scan.ranges[hit] - truth[hit]).max() < 0.06       # 1 cm noise, mm units
    assert np.array_equal(np.isfinite(truth), np.isfinite(scan.ranges))


def test_scans_stream_at_the_rate_the_line_allows(on_pty):
    laser, _, _ = on_pty
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    start = laser.stats["readings"]
    time.sleep(1.0)
    rate = laser.stats["readings"] - start
    # 181 values = 372 bytes: 0.097 s at 38400 baud, so about 10 scans a second
    assert 7 <= rate <= 12


def test_tcp_and_another_angular_mode_in_cm(world):
    emulator, url = start_emulator(world, tcp=True)
    laser = LMS2xxLaser(url, baud=500000, angle=100, resolution=0.25, units="cm",
                        clock=world[0], reply_timeout=0.3)
    try:
        laser.open()
        fw = emulator.firmware
        assert (fw.angle, fw.resolution, fw.units, fw.baud) == (100, 25, "cm", 500000)
        assert laser.wait_for_reading(0, timeout=2.0)
        scan = laser.read()
        assert len(scan.ranges) == 401
        assert np.degrees(scan.angles[[0, -1]]).tolist() == pytest.approx([-50, 50])
        finite = scan.ranges[np.isfinite(scan.ranges)]
        assert len(finite) and np.allclose(finite * 100, np.rint(finite * 100))   # whole cm
    finally:
        laser.close()
        emulator.close()


def test_finds_an_lms_left_at_another_speed_and_streaming(on_pty):
    laser, emulator, url = on_pty
    laser.open()
    laser.close()                               # stops the stream, the LMS stays at 38400
    emulator.firmware.mode = p.Mode.CONTINUOUS  # ... as if the old client never stopped it
    again = LMS2xxLaser(url, baud=9600, angle=180, resolution=1, reply_timeout=0.3)
    try:
        again.open()
        assert again.found_baud == 38400 and emulator.firmware.baud == 9600
        assert again.wait_for_reading(again.stats["readings"], timeout=3.0)
    finally:
        again.close()


def test_nothing_answering_is_a_handshake_error_naming_the_speeds_tried():
    with PtyPair() as pty:
        laser = LMS2xxLaser(pty.path, reply_timeout=0.05, reconnect=False)
        with pytest.raises(HandshakeError, match=r"tried 38400: no reply, 9600: no reply, "
                                                 r"500000: no reply, 19200: no reply"):
            laser.open()
        laser.close()


def test_a_nak_is_reported(world):
    class Nakker(LMS2xxEmulator):
        def _answer(self, telegram):
            self._send(bytes([p.NAK]))
    emulator, url = start_emulator(world, Nakker)
    laser = LMS2xxLaser(url, reply_timeout=0.1, reconnect=False)
    try:
        with pytest.raises(HandshakeError, match="NAK"):
            laser.open()
    finally:
        laser.close()
        emulator.close()


def test_emulator_naks_a_telegram_with_a_bad_crc(on_pty):
    _, emulator, url = on_pty
    port = serial.serial_for_url(url, baudrate=9600, timeout=0.5)
    try:
        bad = bytearray(p.request_status())
        bad[-1] ^= 0x01
        port.write(bytes(bad))
        assert port.read(1) == bytes([p.NAK])
        port.write(p.request_status())
        assert port.read(1) == bytes([p.ACK])
    finally:
        port.close()


def test_options_out_of_range_are_refused():
    with pytest.raises(CommandError, match="resolution 0.25 deg at 180 deg"):
        LMS2xxLaser("/dev/null", angle=180, resolution=0.25)
    with pytest.raises(CommandError, match="baud rate 57600"):
        LMS2xxLaser("/dev/null", baud=57600)


# -- faults -----------------------------------------------------------------------------------------
def test_silence_is_a_link_fault_and_the_laser_comes_back(on_pty):
    laser, emulator, _ = on_pty
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.muted = True
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    assert laser.read() is None
    assert "the device is silent" in laser.link_error
    emulator.muted = False
    assert wait_until(lambda: laser.link_up and laser.read() is not None, timeout=8.0)
    assert laser.stats["link_downs"] == 1 and laser.stats["reconnects"] == 1


def test_a_stale_scan_is_never_returned(on_pty):
    laser, emulator, _ = on_pty
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.muted = True
    time.sleep(laser.stale_after + 0.05)
    assert laser.read() is None                  # before or after the reader noticed


def test_garbage_is_a_link_fault_with_its_reason(on_pty):
    laser, emulator, _ = on_pty
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.fault = "noise"
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    assert "bytes formed no telegram" in laser.link_error
    assert laser.read() is None


def test_bad_crc_is_a_link_fault_naming_the_byte_offset(on_pty):
    laser, emulator, _ = on_pty
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.fault = "crc"
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    assert "bytes formed no telegram" in laser.link_error
    # 372-byte scans: the CRC sits at byte 370 of each; the reason gives its stream offset too
    assert "CRC at byte 370 of the telegram" in laser.link_error
    assert laser.parser.stats.bad_checksum >= 1
    crc = laser.parser.last_crc_error
    assert crc in laser.link_error
    offset = int(crc.split(":")[0].removeprefix("byte "))
    assert offset > 372


def test_unplugged_is_a_link_fault_and_replugging_brings_it_back(on_pty):
    laser, emulator, url = on_pty
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.unplug()
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    assert laser.read() is None
    emulator.serve_pty(link=url)                 # a new cable under the same name
    assert wait_until(lambda: laser.link_up and laser.read() is not None, timeout=8.0)
    assert laser.stats["reconnects"] >= 1


def test_close_stops_the_stream(on_pty):
    laser, emulator, _ = on_pty
    laser.open()
    assert emulator.firmware.streaming
    laser.close()
    assert wait_until(lambda: not emulator.firmware.streaming, timeout=1.0)


def test_a_dropped_tcp_connection_is_a_link_fault_and_the_driver_connects_again(world):
    emulator, url = start_emulator(world, tcp=True)
    laser = LMS2xxLaser.for_profile(HOROS, url, clock=world[0], reply_timeout=0.3)
    try:
        laser.open()
        assert laser.wait_for_reading(0, timeout=2.0)
        emulator.unplug()
        assert wait_until(lambda: not laser.link_up, timeout=2.0)
        assert laser.read() is None
        assert wait_until(lambda: laser.link_up and laser.read() is not None, timeout=8.0)
        assert emulator.connections == 2
    finally:
        laser.close()
        emulator.close()


def test_close_while_reconnecting_leaves_nothing_open(on_pty):
    laser, emulator, _ = on_pty
    laser.open()
    assert laser.wait_for_reading(0, timeout=2.0)
    emulator.muted = True                        # the handshake will probe every speed
    assert wait_until(lambda: not laser.link_up, timeout=2.0)
    time.sleep(0.3)                              # the reader is inside a reconnect by now
    laser.close()
    emulator.muted = False
    time.sleep(2.5)                              # longer than the probing could take
    assert not laser.link_up and laser._port is None and laser.read() is None
