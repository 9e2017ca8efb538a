"""The P2OS firmware emulator: handshake like the firmware, SIPs, watchdog, world readings."""
from __future__ import annotations

import math
import time

import pytest
import serial

from robots.clock import SimClock
from robots.p2os import protocol as p
from robots.p2os.emulator import FIRMWARE_WATCHDOG, Firmware, P2OSEmulator, Snapshot
from robots.profile import load_profile
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")


@pytest.fixture
def world_sim():
    clock = SimClock()
    simulation = Simulation(HOROS, None, 0, clock)
    return clock, simulation


def packets_of(data: bytes) -> list[p.Packet]:
    return p.P2OSParser().feed(data)


def handshake_bytes() -> bytes:
    return p.sync0() + p.sync1() + p.sync2() + p.open_()


def test_handshake_answers_like_the_firmware(world_sim):
    _, simulation = world_sim
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world)
    path = emulator.serve_pty()
    try:
        port = serial.Serial(path, 9600, timeout=1)
        port.write(p.sync0())
        assert port.read(6) == p.sync_echo(0)
        port.write(p.sync1())
        assert port.read(6) == p.sync_echo(1)
        port.write(p.sync2())
        reply = packets_of(port.read(3 + len("horos\0Pioneer\0p2dx\0") + 3))
        assert p.parse_sync2(reply[0].data) == ("horos", "Pioneer", "p2dx")
        port.close()
    finally:
        emulator.close()


def test_out_of_order_sync_is_ignored(world_sim):
    _, simulation = world_sim
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world)
    emulator.receive(p.sync1() + p.sync2() + p.open_())
    assert not emulator.firmware.open


def test_sip_every_100_ms_of_sim_time_and_body_follows_commands(world_sim):
    clock, simulation = world_sim
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    emulator.attach(simulation)
    emulator.tick(0.0)
    assert emulator.sips_sent == 0                    # not open: no SIPs
    emulator.receive(handshake_bytes() + p.enable(True) + p.vel(400) + p.rvel(10))
    for _ in range(20):
        simulation.advance(clock.advance(0.1))
        emulator.tick(clock.now())
    assert emulator.sips_sent == 20
    body = simulation.world.body
    assert body.v == pytest.approx(0.4) and body.w == pytest.approx(math.radians(10))


def test_motors_disabled_after_open_until_enable(world_sim):
    clock, simulation = world_sim
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    emulator.receive(handshake_bytes() + p.vel(300))
    assert emulator.firmware.drive() == (0.0, 0.0)
    emulator.receive(p.enable(True))
    assert emulator.firmware.drive()[0] == pytest.approx(0.3)


def test_firmware_watchdog_stops_after_2_s_and_resumes_on_the_next_packet(world_sim):
    clock, simulation = world_sim
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    emulator.receive(handshake_bytes() + p.enable(True) + p.vel(300))
    t = 0.0
    while t < FIRMWARE_WATCHDOG - 0.15:
        t = clock.advance(0.1)
        emulator.tick(t)
    assert emulator.firmware.drive()[0] == pytest.approx(0.3)
    for _ in range(3):
        emulator.tick(clock.advance(0.1))
    assert emulator.firmware.watchdog_tripped
    assert simulation.world.body.cmd_v == 0.0
    emulator.receive(p.pulse())                       # the real firmware's resume behaviour
    assert simulation.world.body.cmd_v == pytest.approx(0.3)


def test_setv_caps_and_vel2_drives():
    firmware = Firmware(p.FACTORS["p2dx"])
    pose = (0.0, 0.0, 0.0)
    for packet in packets_of(handshake_bytes() + p.enable(True) + p.setv(200) + p.vel(900)):
        firmware.receive(packet, 0.0, pose)
    assert firmware.drive()[0] == pytest.approx(0.2)
    for packet in packets_of(p.setv(2200) + p.vel2(10, 10)):
        firmware.receive(packet, 0.0, pose)
    assert firmware.drive()[0] == pytest.approx(0.2)      # 10 units of 20 mm/s


def test_sip_reports_pose_sonar_bumpers_stall():
    firmware = Firmware(p.FACTORS["p2dx"], sonar_max_range=5.0)
    for packet in packets_of(handshake_bytes() + p.enable(True) + p.sonar(True)):
        firmware.receive(packet, 0.0, (0.0, 0.0, 0.0))
    snap = Snapshot(x=1.0, y=-2.0, th=0.5, v=0.3, w=0.1, sonar=(1.2, math.inf), bumpers=1,
                    stalled=True)
    sip = p.decode_sip(p.unframe(firmware.sip(snap)))
    odo = p.Odometry(p.FACTORS["p2dx"])
    x, y, th = odo.update(sip)
    v, w = odo.velocities(sip)
    assert (x, y, th) == pytest.approx((1.0, -2.0, 0.5), abs=2e-3)
    assert (v, w) == pytest.approx((0.3, 0.1), abs=3e-3)
    assert sip.moving and sip.motors_enabled and sip.sonar_on
    assert sip.front_bumpers and not sip.rear_bumpers
    assert sip.left_stall and sip.right_stall
    ranges = dict(sip.sonar)
    assert ranges[0] * 0.268 == pytest.approx(1200, abs=0.2)
    assert ranges[1] * 0.268 >= 5000                   # no echo: the sonar's maximum
    # 0.268 mm a unit: the nearest unit, none below 0, the 5 m maximum (18 657) for anything
    # beyond it and for no echo at all
    readings = (0.0, -0.5, 0.2, 1.2, 4.99, 5.0, 7.3, math.inf, math.nan)
    assert firmware._sonar_units(readings) == tuple(enumerate(
        (0, 0, 746, 4478, 18619, 18657, 18657, 18657, 18657)))


def test_seto_resets_odometry_to_the_current_pose():
    firmware = Firmware(p.FACTORS["p2dx"])
    for packet in packets_of(handshake_bytes()):
        firmware.receive(packet, 0.0, (0.0, 0.0, 0.0))
    firmware.receive(packets_of(p.seto())[0], 0.0, (3.0, 4.0, math.pi / 2))
    sip = p.decode_sip(p.unframe(firmware.sip(Snapshot(x=3.0, y=5.0, th=math.pi / 2))))
    x, y, th = p.Odometry(p.FACTORS["p2dx"]).update(sip)
    assert (x, y, th) == pytest.approx((1.0, 0.0, 0.0), abs=2e-3)


def test_wrong_baud_gets_no_answer(world_sim):
    _, simulation = world_sim
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, baud=38400)
    path = emulator.serve_pty()
    try:
        port = serial.Serial(path, 9600, timeout=0.2)
        port.write(p.sync0())
        assert port.read(6) == b""
        port.baudrate = 38400
        port.write(p.sync0())
        assert port.read(6) == p.sync_echo(0)
        port.close()
    finally:
        emulator.close()


def test_tcp_transport_and_hang_up_closes_the_robot(world_sim):
    _, simulation = world_sim
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world)
    host, port_number = emulator.serve_tcp("127.0.0.1", 0)
    try:
        port = serial.serial_for_url(f"socket://{host}:{port_number}", timeout=1)
        port.write(handshake_bytes()[:6])
        assert port.read(6) == p.sync_echo(0)
        port.write(p.sync1() + p.sync2() + p.open_())
        deadline = time.monotonic() + 2
        while not emulator.firmware.open and time.monotonic() < deadline:
            time.sleep(0.01)
        assert emulator.firmware.open
        port.close()
        deadline = time.monotonic() + 2
        while emulator.firmware.open and time.monotonic() < deadline:
            time.sleep(0.01)
        assert not emulator.firmware.open
    finally:
        emulator.close()
