"""The P2OS driver over a real pty (and TCP) against the firmware emulator."""
from __future__ import annotations

import math
import statistics
import threading
import time

import pytest
import serial
from hypothesis import given, settings, strategies as st

from robots.base import base_classes
from robots.clock import RealClock, SimClock
from robots.exceptions import HandshakeError, LinkError
from robots.link import PtyPair
from robots.p2os import protocol as p
from robots.p2os.driver import P2OSBase
from robots.p2os.emulator import P2OSEmulator
from robots.profile import load_profile
from robots.sim.simulation import Simulation

HOROS = load_profile("horos")
LIMITS = HOROS.limits


def wait_until(predicate, timeout=3.0, step=0.005):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(step)
    return predicate()


def velocity_packets(emulator, since=0.0):
    """(arrival, kind, argument) of every VEL/RVEL the emulator received after `since`."""
    return [(t, pkt.kind, p.decode_argument(pkt.data)) for t, pkt in list(emulator.received)
            if t >= since and pkt.kind in (p.Cmd.VEL, p.Cmd.RVEL)]


@pytest.fixture
def fast():
    """The default simulated HOROS on a simulated clock: driver + emulator in lock-step."""
    clock = SimClock()
    simulation = Simulation(HOROS, None, 0, clock)
    base = P2OSBase.for_simulation(HOROS, simulation, clock)
    base.open()

    def tick(dt=0.1):
        simulation.advance(clock.advance(dt))
        base.poll()
    yield base, simulation, clock, tick
    base.close()


@pytest.fixture
def realtime(tmp_path):
    """A real-time emulator on a pty behind a stable symlink, and a driver on it."""
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    emulator.attach(simulation)
    link = str(tmp_path / "ttyP2OS")
    emulator.serve_pty(link=link)
    emulator.start_clock(simulation)
    base = P2OSBase(LIMITS, link, subclass="p2dx", clock=clock, reply_timeout=0.2)
    yield base, emulator, link
    base.close()
    emulator.close()


def test_registered_as_a_base_plugin():
    assert base_classes()["p2os"] is P2OSBase


# -- handshake -------------------------------------------------------------------------------
def test_handshake_picks_factors_and_enables_with_zero_first(fast):
    base, simulation, _, _ = fast
    assert base.robot_id == ("horos", "Pioneer", "p2dx")
    assert base.factors is p.FACTORS["p2dx"]
    kinds = [pkt.kind for _, pkt in base.emulator.received]
    assert kinds[:4] == [0, 1, 2, p.Cmd.OPEN]
    assert kinds.index(p.Cmd.VEL) < kinds.index(p.Cmd.ENABLE)
    assert p.Cmd.SONAR in kinds
    assert base.emulator.firmware.motors and base.emulator.firmware.sonar_on


def test_handshake_with_no_answer_is_a_clear_error():
    with PtyPair() as silent:
        base = P2OSBase(LIMITS, silent.path, retries=1, reply_timeout=0.03)
        with pytest.raises(HandshakeError) as info:
            base.open()
        message = str(info.value)
        assert silent.path in message and "SYNC" in message
        assert "9600" in message and "57600" in message
        base.close()


def test_unopenable_port_is_a_link_error(tmp_path):
    base = P2OSBase(LIMITS, str(tmp_path / "no-such-tty"))
    with pytest.raises(LinkError, match="cannot open"):
        base.open()


def test_handshake_when_the_robot_is_still_open(realtime):
    base, emulator, link = realtime
    earlier = serial.Serial(link, 9600, timeout=0.5)    # an earlier client that never closed
    earlier.write(p.sync0() + p.sync1() + p.sync2() + p.open_())
    assert wait_until(lambda: emulator.firmware.open)
    earlier.close()
    assert wait_until(lambda: emulator.sips_sent > 2)
    base.open()
    assert base.robot_id[2] == "p2dx" and base.link_up
    kinds = [pkt.kind for _, pkt in emulator.received]
    first_sync = kinds.index(0, 4)                      # after the earlier client's packets
    assert p.Cmd.CLOSE in kinds[first_sync:]            # it had to close the robot first
    assert wait_until(lambda: base.read_state().extra.get("sips", 0) >= 2)


def test_handshake_at_the_wrong_baud_falls_back():
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock, baud=38400)
    path = emulator.serve_pty()
    emulator.start_clock(simulation)
    base = P2OSBase(LIMITS, path, reply_timeout=0.05, clock=clock)
    try:
        base.open()
        assert base.connected_baud == 38400
        assert base.read_state().link_up
    finally:
        base.close()
        emulator.close()


# -- driving -----------------------------------------------------------------------------------
def test_default_simulated_horos_drives_over_the_pty(fast):
    base, simulation, _, tick = fast
    for _ in range(30):
        tick()
        base.command(0.3, 0.2)
    state = base.read_state()
    body = simulation.world.odometry          # what the encoders counted
    assert state.link_up and state.motors_enabled
    assert (state.x, state.y) == pytest.approx((body.x, body.y), abs=0.05)
    assert state.v == pytest.approx(0.3, abs=0.01)
    assert state.w == pytest.approx(0.2, abs=0.02)
    assert len(state.sonar) == 16
    expected = simulation.world.sonar_ranges()
    for got, want in zip(state.sonar, expected):
        if math.isinf(want):
            assert math.isinf(got)
        else:
            assert got == pytest.approx(want, abs=0.35)  # the robot moved since the SIP


def test_fast_runs_are_deterministic():
    def run():
        clock = SimClock()
        simulation = Simulation(HOROS, None, 0, clock)
        base = P2OSBase.for_simulation(HOROS, simulation, clock)
        base.open()
        states = []
        for i in range(40):
            simulation.advance(clock.advance(0.1))
            base.poll()
            base.command(0.4 * math.sin(i / 5), 0.5 * math.cos(i / 7))
            states.append(base.read_state())
        base.close()
        return [(s.t, s.x, s.y, s.th, s.v, s.w, s.sonar) for s in states]
    assert run() == run()


def test_clamping_and_nan(fast):
    base, _, _, tick = fast
    tick()
    base.command(5.0, -10.0)
    assert base.emulator.firmware.vel == 600 and base.emulator.firmware.rvel == -90
    base.command(math.nan, math.inf)
    assert base.emulator.firmware.vel == 0 and base.emulator.firmware.rvel == 0
    base.command(0.25, math.radians(30))
    assert base.emulator.firmware.vel == 250 and base.emulator.firmware.rvel == 30


def test_keepalive_only_while_commands_are_fresh_and_watchdog_in_sim_time(fast):
    base, _, _, tick = fast
    emulator = base.emulator
    start = len(velocity_packets(emulator))
    for _ in range(20):                                  # 2 s of the same fresh command
        base.command(0.3, 0.0)
        tick()
    sent = velocity_packets(emulator)[start:]
    assert 2 * 4 <= len(sent) <= 2 * 6                   # changed once + a keep-alive every 0.5 s
    before = len(velocity_packets(emulator))
    tick(0.1)
    tick(0.1)                                            # 0.2 s without a command
    zero = velocity_packets(emulator)[before:]
    assert [(k, a) for _, k, a in zero] == [(p.Cmd.VEL, 0), (p.Cmd.RVEL, 0)]
    quiet = len(velocity_packets(emulator))
    for _ in range(30):                                  # 3 s more: nothing is sent at all
        tick()
    assert len(velocity_packets(emulator)) == quiet
    assert base.read_state().link_up                     # SIPs still flow


def test_link_down_after_three_missed_sips_in_sim_time(fast):
    base, _, _, tick = fast
    tick()
    assert base.read_state().link_up
    base.emulator.firmware.open = False                 # the controller stops streaming
    tick(0.1)
    tick(0.1)
    tick(0.1)
    assert base.link_up
    tick(0.1)
    assert not base.link_up and not base.read_state().link_up
    assert "no SIP" in base.last_error


def test_watchdog_sends_zero_within_200_ms_over_a_pty(realtime):
    """Measured over many trials: last fresh command -> first zero byte at the firmware."""
    base, emulator, _ = realtime
    base.open()
    latencies = []
    for trial in range(40):
        speed = 0.1 + 0.01 * (trial % 5)
        last_fresh = time.monotonic()
        base.command(speed, 0.0)                         # the tick loop then goes silent
        assert wait_until(lambda: any(k == p.Cmd.VEL and a == 0
                                      for _, k, a in velocity_packets(emulator, last_fresh)),
                          timeout=1.0)
        first_zero = min(t for t, k, a in velocity_packets(emulator, last_fresh)
                         if k == p.Cmd.VEL and a == 0)
        latencies.append(first_zero - last_fresh)
    assert max(latencies) <= 0.200, latencies
    assert base.stats["watchdog_stops"] >= 40
    print(f"watchdog: median {statistics.median(latencies) * 1e3:.1f} ms, "
          f"max {max(latencies) * 1e3:.1f} ms over {len(latencies)} trials")


def test_unplug_and_reconnect_sends_zero_first_and_never_resumes_by_itself(realtime, tmp_path):
    base, emulator, link = realtime
    base.open()
    feeding = threading.Event()
    feeding.set()
    stop = threading.Event()

    def tick_loop():
        while not stop.is_set():
            if feeding.is_set():
                base.command(0.3, 0.1)
            time.sleep(0.05)
    loop = threading.Thread(target=tick_loop, daemon=True)
    loop.start()
    try:
        assert wait_until(lambda: emulator.firmware.vel == 300)
        emulator.unplug()                                # pull the cable
        assert wait_until(lambda: not base.read_state().link_up, timeout=2.0)
        feeding.clear()                                  # the tick loop stops commanding
        replugged = time.monotonic()
        emulator.serve_pty(link=link)                    # plug a new line in under the same name
        assert wait_until(lambda: base.link_up, timeout=5.0)
        assert base.stats["reconnects"] == 1
        # the emulator's reader may file the ENABLE a moment after the driver says link up
        assert wait_until(lambda: any(pkt.kind == p.Cmd.ENABLE
                                      for t, pkt in list(emulator.received) if t >= replugged))
        after = [(pkt.kind, p.decode_argument(pkt.data)) for t, pkt in list(emulator.received)
                 if t >= replugged]
        kinds = [k for k, _ in after]
        enable = kinds.index(p.Cmd.ENABLE)
        assert (p.Cmd.VEL, 0) in after[:enable] and (p.Cmd.RVEL, 0) in after[:enable]
        assert all(a == 0 for k, a in after[:enable] if k in (p.Cmd.VEL, p.Cmd.RVEL))
        time.sleep(0.5)                                  # nothing resumes motion by itself
        assert all(a == 0 for _, k, a in velocity_packets(emulator, replugged))
        assert emulator.firmware.drive() == (0.0, 0.0)
        feeding.set()                                    # a fresh command drives again
        assert wait_until(lambda: emulator.firmware.vel == 300)
    finally:
        stop.set()
        loop.join()


def test_tcp_url(tmp_path):
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    emulator = P2OSEmulator.for_profile(HOROS, simulation.world, clock=clock)
    emulator.attach(simulation)
    host, port = emulator.serve_tcp()
    emulator.start_clock(simulation)
    base = P2OSBase(LIMITS, f"socket://{host}:{port}", clock=clock)
    try:
        base.open()
        base.command(0.2, 0.0)
        assert wait_until(lambda: emulator.firmware.vel == 200)
        # the tick loop keeps commanding; the state comes back through the SIPs
        assert wait_until(lambda: base.command(0.2, 0.0) or base.read_state().v > 0.05, step=0.05)
    finally:
        base.close()
        emulator.close()


def test_sip_bumpers_and_stall_reach_the_state():
    from robots.p2os.emulator import Firmware, Snapshot
    firmware = Firmware(p.FACTORS["p2dx"])
    firmware.motors = True
    sip = p.decode_sip(p.unframe(firmware.sip(Snapshot(bumpers=2, stalled=True))))
    base = P2OSBase(LIMITS, "loop://")
    base._on_sip(sip)
    state = base.read_state()
    assert state.bumpers == 2 and state.stalled and state.motors_enabled
    assert state.battery == pytest.approx(12.5)


def test_silent_controller_means_link_down_then_reconnect_in_real_time(realtime):
    base, emulator, _ = realtime
    base.open()
    assert wait_until(lambda: base.stats["sips"] >= 3)
    silenced = time.monotonic()
    emulator.firmware.open = False                      # SIPs stop; the port stays fine
    assert wait_until(lambda: base.stats["link_downs"] == 1, timeout=2.0)
    noticed = time.monotonic() - silenced
    assert noticed >= 0.3                                # not before 3 cycles were missed
    assert "no SIP" in base.last_error
    assert wait_until(lambda: base.link_up and base.stats["reconnects"] == 1, timeout=5.0)

    def kinds_since_silence():
        return [pkt.kind for t, pkt in list(emulator.received) if t >= silenced]
    # the driver counts the reconnect once it has written its start-up; the emulator reads it
    # on its own thread, which a loaded machine may run a little later
    assert wait_until(lambda: p.Cmd.ENABLE in kinds_since_silence(), timeout=2.0)
    kinds = kinds_since_silence()
    assert kinds.index(p.Cmd.VEL) < kinds.index(p.Cmd.ENABLE)


def test_factors_come_from_the_sync2_subclass_not_the_hint():
    clock = RealClock()
    simulation = Simulation(HOROS, None, 0, clock)
    emulator = P2OSEmulator(simulation.world, subclass="p2at", clock=clock)
    emulator.attach(simulation)
    path = emulator.serve_pty()
    emulator.start_clock(simulation)
    base = P2OSBase(LIMITS, path, subclass_hint="p2dx", clock=clock)
    try:
        base.open()
        assert base.robot_id[2] == "p2at"
        assert base.factors is p.FACTORS["p2at"]
        assert wait_until(lambda: base.read_state().extra.get("subclass") == "p2at")
        body = simulation.world.body
        state = base.read_state()
        assert (state.x, state.y) == pytest.approx((body.x, body.y), abs=0.01)
    finally:
        base.close()
        emulator.close()


finite_or_not = st.one_of(st.floats(allow_nan=True, allow_infinity=True),
                          st.floats(-5, 5))


@settings(max_examples=150, deadline=None)
@given(v=finite_or_not, w=finite_or_not)
def test_any_command_reaches_the_wire_clamped_and_nan_as_zero(fast_base, v, w):
    base, emulator = fast_base
    base.command(v, w)
    vel, rvel = emulator.firmware.vel, emulator.firmware.rvel
    assert abs(vel) <= round(LIMITS.max_speed * 1000)
    assert abs(rvel) <= round(math.degrees(LIMITS.max_turn_rate))
    if not math.isfinite(v):
        assert vel == 0
    else:
        assert vel == pytest.approx(max(-600, min(600, v * 1000)), abs=0.5 + 1e-9)
    if not math.isfinite(w):
        assert rvel == 0


@pytest.fixture(scope="module")
def fast_base():
    clock = SimClock()
    simulation = Simulation(HOROS, None, 0, clock)
    base = P2OSBase.for_simulation(HOROS, simulation, clock)
    base.open()
    yield base, base.emulator
    base.close()
