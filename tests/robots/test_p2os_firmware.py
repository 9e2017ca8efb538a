"""The P2OS emulator behaves as the manuals describe the controller (../shared/protocols/p2os.md):
each test states the described behaviour and checks it through the wire (commands in, SIPs and
the simulated body out), not through the emulator's internals."""
from __future__ import annotations

import math
import socket
import time

import numpy as np
import pytest

from robots.clock import SimClock
from robots.p2os import protocol as p
from robots.p2os.emulator import P2OSEmulator
from robots.profile import load_profile
from robots.sim.floor import Floor
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")
ANGLE_UNITS_PER_DEG = 4096 / 360
OPEN_FLOOR = Floor(name="open", segments=np.zeros((0, 4)), places={})   # nothing to run into


class Wire:
    """The emulator driven through its byte interface on a simulated clock; SIPs collected."""

    def __init__(self, subclass: str = "p2dx") -> None:
        self.clock = SimClock()
        self.simulation = Simulation(HOROS, None, 0, self.clock, floor=OPEN_FLOOR)
        self.emulator = P2OSEmulator(self.simulation.world, subclass=subclass, clock=self.clock)
        self.emulator.attach(self.simulation)
        self.out = bytearray()
        self.emulator._send = lambda data: self.out.extend(data)   # the wire towards the client
        self.parser = p.P2OSParser()
        self.send(p.sync0() + p.sync1() + p.sync2() + p.open_())

    def send(self, data: bytes) -> None:
        self.emulator.receive(data)

    def run(self, seconds: float, step: float = 0.02) -> None:
        """Let time pass, with a PULSE every 0.5 s as a client does (the watchdog is 2 s)."""
        for i in range(round(seconds / step)):
            now = self.clock.advance(step)
            self.simulation.advance(now)
            self.emulator.tick(now)
            if i % 25 == 24:
                self.send(p.pulse())

    def packets(self) -> list[p.Packet]:
        data, self.out = bytes(self.out), bytearray()
        return self.parser.feed(data)

    def sips(self) -> list[p.SIP]:
        return [p.decode_sip(k) for k in self.packets() if k.kind in p.SIP_TYPES]

    @property
    def body(self):
        return self.simulation.world.body


@pytest.fixture
def wire():
    return Wire()


def heading_deg(sip: p.SIP) -> float:
    return math.degrees(p.normalize_angle(sip.thpos * p.ANGLE_CONV))


# -- motion commands ---------------------------------------------------------------------------
def test_head_turns_to_an_absolute_heading_and_control_reports_the_setpoint(wire):
    """HEAD (12): absolute heading in degrees; CONTROL is the heading servo's setpoint."""
    wire.send(p.enable(True) + p.head(90))
    wire.run(4.0)
    sip = wire.sips()[-1]
    assert heading_deg(sip) == pytest.approx(90, abs=1.0)
    assert sip.control == pytest.approx(90 * ANGLE_UNITS_PER_DEG, abs=1)
    assert abs(wire.body.w) < 0.02                      # arrived and holding
    wire.send(p.head(-30))
    wire.run(4.0)
    assert heading_deg(wire.sips()[-1]) == pytest.approx(-30, abs=1.0)


def test_dhead_turns_relative_to_the_current_heading(wire):
    """DHEAD (13): relative heading in degrees, + counter-clockwise."""
    wire.send(p.enable(True) + p.head(40))
    wire.run(3.0)
    wire.send(p.dhead(-100))
    wire.run(4.0)
    assert heading_deg(wire.sips()[-1]) == pytest.approx(-60, abs=1.5)


def test_head_is_in_the_odometry_frame_set_by_seto(wire):
    """SETO (7) resets odometry to 0,0,0 here; HEAD 0 then means the heading at SETO."""
    wire.send(p.enable(True) + p.head(60))
    wire.run(3.0)
    world_heading = wire.body.th
    wire.send(p.seto() + p.head(0) + p.dhead(45))
    wire.run(3.0)
    wire.send(p.head(0))
    wire.run(3.0)
    assert wire.body.th == pytest.approx(world_heading, abs=math.radians(1.0))
    assert heading_deg(wire.sips()[-1]) == pytest.approx(0, abs=1.0)


@pytest.mark.parametrize("mm", [500, -300])
def test_move_travels_a_relative_distance_and_stops(wire, mm):
    """MOVE (8): relative move in mm."""
    wire.send(p.enable(True) + p.move(mm))
    wire.run(5.0)
    assert wire.body.x * 1000 == pytest.approx(mm, abs=5)
    assert wire.body.v == pytest.approx(0.0, abs=1e-3)


def test_vel_ends_a_move_and_rvel_ends_a_heading(wire):
    wire.send(p.enable(True) + p.move(5000) + p.head(90))
    wire.run(0.5)
    wire.send(p.vel(0) + p.rvel(0))
    wire.run(2.0)
    assert wire.body.v == 0.0 and wire.body.w == 0.0
    assert wire.body.x < 0.5


def test_rotate_turns_at_a_rotational_velocity(wire):
    """ROTATE (9): ARIA's command list describes it as rotate at (int) deg/s."""
    wire.send(p.enable(True) + p.rotate(30))
    wire.run(2.0)
    assert math.degrees(wire.body.w) == pytest.approx(30, abs=0.5)


def test_stop_decelerates_and_keeps_the_motors_enabled_estop_stops_at_once(wire):
    """STOP (29): stop, motors stay enabled. ESTOP (55): overrides the deceleration."""
    wire.send(p.enable(True) + p.vel(500))
    wire.run(3.0)
    wire.send(p.stop())
    wire.run(0.1)
    assert 0.0 < wire.body.v < 0.5                     # still slowing down
    wire.run(2.0)
    sip = wire.sips()[-1]
    assert wire.body.v == 0.0 and sip.motors_enabled
    wire.send(p.vel(500))
    wire.run(3.0)
    wire.send(p.estop())
    wire.run(0.02)
    assert wire.body.v == 0.0


# -- limits and accelerations -------------------------------------------------------------------
@pytest.mark.parametrize("subclass,max_vel,max_rvel", [("p2dx", 2200, 500), ("p2at", 1200, 300)])
def test_the_firmware_limits_are_the_subclass_absolute_limits_not_our_safe_ones(
        subclass, max_vel, max_rvel):
    """p2os.md §7: MaxVel/MaxRVel per subclass are absolute limits (our profile says 0.6 m/s)."""
    wire = Wire(subclass)
    wire.send(p.enable(True) + p.seta(3000) + p.vel(1000))
    wire.run(4.0)
    assert wire.body.v == pytest.approx(1.0, abs=1e-3)          # well above the profile's 0.6
    wire.send(p.vel(5000))
    wire.run(4.0)
    assert wire.body.v * 1000 == pytest.approx(max_vel, abs=1)
    wire.send(p.vel(0) + p.setra(2000) + p.rvel(1000))
    wire.run(4.0)
    assert math.degrees(wire.body.w) == pytest.approx(max_rvel, abs=0.5)


def test_setv_and_setrv_cap_vel_and_rvel_but_never_above_the_absolute_limits(wire):
    """SETV (6) / SETRV (10): max velocities that VEL / RVEL can reach."""
    wire.send(p.enable(True) + p.setv(400) + p.setrv(20) + p.vel(900) + p.rvel(-60))
    wire.run(4.0)
    assert wire.body.v == pytest.approx(0.4) and math.degrees(wire.body.w) == pytest.approx(-20)
    wire.send(p.setv(9000) + p.vel(9000))
    wire.run(6.0)
    assert wire.body.v == pytest.approx(2.2)


def test_seta_sign_selects_acceleration_or_deceleration(wire):
    """SETA (5): + sets the translational acceleration, - the deceleration, mm/s²."""
    wire.send(p.enable(True) + p.seta(1000) + p.seta(-250) + p.vel(1000))
    wire.run(0.5)
    assert wire.body.v == pytest.approx(0.5, abs=0.03)          # 1000 mm/s² up
    wire.run(1.0)
    wire.send(p.vel(0))
    wire.run(1.0)
    assert wire.body.v == pytest.approx(0.75, abs=0.03)         # 250 mm/s² down


def test_setra_sign_selects_rotational_acceleration_or_deceleration(wire):
    """SETRA (23): + rotational acceleration, - deceleration, deg/s²."""
    wire.send(p.enable(True) + p.setra(200) + p.setra(-50) + p.rvel(100))
    wire.run(0.25)
    assert math.degrees(wire.body.w) == pytest.approx(50, abs=3)
    wire.run(1.0)
    wire.send(p.rvel(0))
    wire.run(1.0)
    assert math.degrees(wire.body.w) == pytest.approx(50, abs=3)


def test_config_is_answered_with_a_configpac_of_the_limits_and_settings(wire):
    """CONFIG (18): the controller answers with a CONFIGpac (type 0x20)."""
    wire.send(p.setv(700) + p.setrv(45) + p.seta(800) + p.seta(-400) + p.config())
    configs = [k for k in wire.packets() if k.kind == p.CONFIG_TYPE]
    assert len(configs) == 1
    config = p.decode_config(configs[0])
    assert config["subtype"] == "p2dx"
    assert (config["trans_vel_top"], config["rot_vel_top"]) == (2200, 500)
    assert (config["trans_vel_max"], config["rot_vel_max"]) == (700, 45)
    assert (config["trans_accel"], config["trans_decel"]) == (800, 400)


# -- sonar and SIP ------------------------------------------------------------------------------
def test_sonar_fires_from_open_and_sonar_0_1_switches_it(wire):
    """The manuals: sonar fires by default after OPEN; SONAR (28) bit 0 switches it."""
    wire.run(0.3)
    sips = wire.sips()
    assert sips and all(s.sonar_on and len(s.sonar) == 16 for s in sips)
    wire.send(p.sonar(False))
    wire.run(0.3)
    assert all(not s.sonar_on and not s.sonar for s in wire.sips())
    wire.send(p.sonar(True))
    wire.run(0.3)
    assert all(s.sonar for s in wire.sips())


class LaggingClock:
    """A real-time clock whose `now` a test sets (the world lags it, as between tick steps)."""
    simulated = False

    def __init__(self) -> None:
        self.t = 0.0

    def now(self) -> float:
        return self.t


def test_the_sip_position_is_sampled_at_sip_time_not_at_the_last_world_step():
    clock = LaggingClock()
    simulation = Simulation(HOROS, None, 0, SimClock(), floor=OPEN_FLOOR)
    emulator = P2OSEmulator(simulation.world, clock=clock)
    emulator.attach(simulation)
    sent = bytearray()
    emulator._send = sent.extend
    emulator.receive(p.sync0() + p.sync1() + p.sync2() + p.open_() + p.enable(True) +
                     p.vel(1000))
    body = simulation.world.body
    body.v = body.cmd_v = 1.0                        # cruising at 1 m/s along x
    simulation.advance(1.0)                          # the world's last step: t = 1.0
    x_at_step = simulation.world.odometry.x          # what the encoders counted by then
    clock.t = 1.08                                   # the SIP goes out 80 ms later
    emulator.tick(clock.t)
    sip = [p.decode_sip(k) for k in p.P2OSParser().feed(bytes(sent)) if k.kind in p.SIP_TYPES][-1]
    x_mm = sip.xpos * p.FACTORS["p2dx"].dist
    assert x_mm == pytest.approx((x_at_step + 0.08) * 1000, abs=2)


# -- TCP: take-over and CLOSE -------------------------------------------------------------------
def handshake(conn: socket.socket) -> list[p.Packet]:
    parser, got = p.P2OSParser(), []
    for stage in range(3):
        conn.sendall(p.command(stage))
        deadline = time.monotonic() + 2
        while not any(k.kind == stage for k in got) and time.monotonic() < deadline:
            got += parser.feed(conn.recv(4096))
    return got


def closed_by_peer(conn: socket.socket, timeout: float = 2.0) -> bool:
    conn.settimeout(0.1)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            if conn.recv(4096) == b"":
                return True
        except socket.timeout:
            continue
        except OSError:
            return True
    return False


@pytest.fixture
def tcp_emulator():
    simulation = Simulation(HOROS, None, 0, SimClock())
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world)
    host, port = emulator.serve_tcp("127.0.0.1", 0)
    yield emulator, (host, port)
    emulator.close()


def test_a_new_tcp_client_takes_over_from_one_that_stays_connected(tcp_emulator):
    """As on a serial line, whoever syncs is answered: a client that keeps its socket open
    (after CLOSE, or just idle) does not lock the next one out."""
    emulator, address = tcp_emulator
    first = socket.create_connection(address)
    assert [k.kind for k in handshake(first)][:3] == [0, 1, 2]
    first.sendall(p.open_() + p.enable(True))
    second = socket.create_connection(address)
    got = handshake(second)
    assert p.parse_sync2(next(k for k in got if k.kind == 2).data)[2] == "p2dx"
    assert closed_by_peer(first)                          # the old client was hung up
    assert not emulator.firmware.motors                   # ...and left the robot stopped
    first.close()
    second.close()


def test_close_ends_the_tcp_session(tcp_emulator):
    emulator, address = tcp_emulator
    conn = socket.create_connection(address)
    handshake(conn)
    conn.sendall(p.open_() + p.enable(True) + p.vel(200))
    time.sleep(0.2)
    conn.sendall(p.close())
    assert closed_by_peer(conn)
    assert not emulator.firmware.open
    conn.close()
    again = socket.create_connection(address)             # and the next client is served
    assert [k.kind for k in handshake(again)][:3] == [0, 1, 2]
    again.close()


# -- our driver keeps our limits ----------------------------------------------------------------
def test_our_driver_still_applies_the_profiles_safe_limits():
    clock = SimClock()
    simulation = Simulation(HOROS, None, 0, clock, floor=OPEN_FLOOR)
    from robots.p2os.driver import P2OSBase
    base = P2OSBase.for_simulation(HOROS, simulation, clock)
    base.open()
    try:
        for _ in range(40):
            base.command(5.0, 10.0)
            simulation.advance(clock.advance(0.1))
            base.poll()
        body = simulation.world.body
        assert body.v == pytest.approx(HOROS.limits.max_speed, abs=1e-3)
        assert body.w == pytest.approx(HOROS.limits.max_turn_rate, abs=1e-3)
        assert base.emulator.firmware.max_vel == round(HOROS.limits.max_speed * 1000)
    finally:
        base.close()


def test_switching_one_sonar_array_off_does_not_blind_the_robot(wire):
    """SONAR bits 1..3 pick an array (6 turns array 3 off); arrays are not modelled, so the
    emulator keeps every sonar firing rather than switch them all off."""
    wire.send(p.sonar(False, array=3))
    wire.run(0.3)
    assert all(s.sonar for s in wire.sips())
