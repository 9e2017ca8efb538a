"""RFlexBase against the controller emulator in lock-step with a simulated clock (deterministic),
and the driver's pure parts (odometry, sonar mapping, options)."""
from __future__ import annotations

import math

import pytest

from rflex_helpers import PERSES, BoxWorld, StepSim
from robots.base import base_classes
from robots.clock import SimClock
from robots.exceptions import LinkError, ProfileError
from robots.link import LockStep
from robots.rflex import protocol as p
from robots.rflex.driver import ANGLE_CONV, DIST_CONV, RFlexBase
from robots.rflex.emulator import RFlexEmulator
from robots.sim.simulation import Simulation


def lockstep_pair(world=None, start_counts=(0, 0)):
    """Driver and emulator on a pty, stepped by a simulated clock."""
    world = world or BoxWorld()
    sim = StepSim(world)
    clock = SimClock()
    lockstep = LockStep()
    emulator = RFlexEmulator(world, clock=clock, lockstep=lockstep, start_counts=start_counts)
    emulator.attach(sim)
    base = RFlexBase(PERSES.limits, emulator.serve_pty(), clock=clock, lockstep=lockstep)
    base._emulator = emulator
    base.open()
    return base, emulator, sim, clock


def tick(base, sim, clock, dt=0.1):
    clock.advance(dt)
    sim.advance(clock.now())
    base.poll()


def set_dirs(emulator, since=-math.inf):
    return [(t, c) for t, c in emulator.controller.commands if isinstance(c, p.SetDir) and t >= since]


def test_registered_as_the_rflex_base():
    assert base_classes()["rflex"] is RFlexBase


def test_start_sequence_releases_brake_and_enables_reports_and_sonar():
    base, emulator, sim, clock = lockstep_pair()
    try:
        tick(base, sim, clock)
        kinds = [c for _, c in emulator.controller.commands]
        assert kinds[:4] == [p.ReportRequest(p.REPORT_PERIOD_US, 3), p.DioRequest(p.REPORT_PERIOD_US),
                             p.Simple(p.MOT, p.MOT_SET_DEFAULTS), p.Simple(p.MOT, p.MOT_BRAKE_RELEASE)]
        assert p.SonarRun(True) in kinds
        state = base.read_state()
        assert state.link_up and state.motors_enabled
        assert state.battery == pytest.approx(26.0)
    finally:
        base.close()
    assert emulator.controller.brake                       # close sets the brake again


def test_both_axes_resent_every_100_ms_zeros_included():
    base, emulator, sim, clock = lockstep_pair()
    try:
        for _ in range(20):
            tick(base, sim, clock)
        sent = set_dirs(emulator, since=0.15)
        per_axis = {axis: [c for _, c in sent if c.axis == axis] for axis in (0, 1)}
        assert 18 <= len(per_axis[0]) <= 20 and len(per_axis[0]) == len(per_axis[1])
        assert all(c.velocity == 0 for c in per_axis[0] + per_axis[1])
    finally:
        base.close()


def test_a_caller_commanding_every_tick_gets_one_pair_per_tick_not_a_stale_resend_first():
    # rflex.md §8: both axes at 10 Hz, not back to back. The tick's poll used to resend the last
    # tick's command and the tick's command followed at the same instant
    base, emulator, sim, clock = lockstep_pair()
    try:
        tick(base, sim, clock)
        for i in range(20):
            tick(base, sim, clock)
            base.command(0.05 * (i % 4), 0.0)              # a new command most ticks
        sent = [(t, c) for t, c in set_dirs(emulator, since=0.15) if c.axis == 0]
        times = [t for t, _ in sent]
        assert len(times) == len(set(times)) == 20             # one per tick, none doubled
        assert [c.velocity for _, c in sent] == [
            p.velocity_units(0.05 * (i % 4), base.dist_conv) for i in range(20)]
        quiet_from = clock.now()                               # the caller stops commanding
        for _ in range(10):
            tick(base, sim, clock)
        resent = [t for t, c in set_dirs(emulator, since=quiet_from + 1e-6) if c.axis == 0]
        assert resent and resent[0] - quiet_from <= 0.2 + 1e-9  # the driver resends again
        assert all(b - a == pytest.approx(0.1) for a, b in zip(resent, resent[1:]))
    finally:
        base.close()


def test_drives_the_body_and_integrates_odometry_in_world_frame():
    clock = SimClock()
    sim = Simulation(PERSES, None, 0, clock)
    base = RFlexBase.for_simulation(PERSES, sim, clock)
    base.open()
    try:
        for _ in range(50):
            clock.advance(0.1)
            sim.advance(clock.now())
            base.poll()
            base.command(0.3, 0.25)
        state, body = base.read_state(), sim.world.odometry      # what the encoders counted
        assert state.t == pytest.approx(clock.now())
        assert math.hypot(state.x - body.x, state.y - body.y) < 0.005
        assert abs(state.th - body.th) < 0.005
        assert state.v == pytest.approx(body.v, abs=1e-4) and state.w == pytest.approx(body.w, abs=1e-4)
        truth = sim.world.body                                   # drifted from, but close to
        assert 0.0 < math.hypot(state.x - truth.x, state.y - truth.y) < 0.1
        truth = sim.world.sonar_ranges()
        assert len(state.sonar) == 48
        for got, want in zip(state.sonar, truth):
            assert (got == want == math.inf) or abs(got - want) <= 1 / p.SONAR_RAW_PER_M
    finally:
        base.close()


def test_a_lockstep_run_is_deterministic():
    def run():
        clock = SimClock()
        sim = Simulation(PERSES, None, 3, clock)
        base = RFlexBase.for_simulation(PERSES, sim, clock)
        base.open()
        trace = []
        try:
            for i in range(30):
                clock.advance(0.1)
                sim.advance(clock.now())
                base.poll()
                base.command(0.2 if i < 20 else 0.0, 0.3)
                s = base.read_state()
                trace.append((s.t, s.x, s.y, s.th, s.v, s.w, s.sonar))
        finally:
            base.close()
        return trace
    assert run() == run()


def test_watchdog_sends_zero_within_200_ms_of_the_last_command():
    base, emulator, sim, clock = lockstep_pair()
    try:
        tick(base, sim, clock, 0.05)
        base.command(0.4, 0.0)
        last_command = clock.now()
        for _ in range(10):
            tick(base, sim, clock, 0.05)
        sent = [(t, c) for t, c in set_dirs(emulator, since=last_command) if c.axis == 0]
        first_zero = next(t for t, c in sent if c.velocity == 0)
        assert any(c.velocity > 0 for _, c in sent)
        assert first_zero - last_command <= 0.2 + 1e-9
        assert base.read_state().extra["watchdog_expirations"] == 1
        assert emulator.world.body.cmd_v == 0.0
    finally:
        base.close()


def test_commands_are_clamped_and_nan_is_zero():
    base, emulator, sim, clock = lockstep_pair()
    try:
        tick(base, sim, clock)
        base.command(float("nan"), 10.0)
        translation, rotation = [c for _, c in set_dirs(emulator)][-2:]
        assert translation.velocity == 0
        assert abs(rotation.velocity - PERSES.limits.max_turn_rate * ANGLE_CONV) <= 128
        base.command(-5.0, float("inf"))
        translation, rotation = [c for _, c in set_dirs(emulator)][-2:]
        assert abs(translation.velocity + PERSES.limits.max_speed * DIST_CONV) <= 128
        assert rotation.velocity == 0
    finally:
        base.close()


def test_odometry_survives_counter_wrap():
    base, emulator, sim, clock = lockstep_pair(start_counts=(2**31 - 20_000, -(2**31) + 5_000))
    try:
        for _ in range(30):
            tick(base, sim, clock)
            base.command(0.5, -0.5)
        positions = emulator.controller.axes
        assert positions[0].position > 2**31 and positions[1].position < -(2**31)   # both wrapped
        state, body = base.read_state(), emulator.world.body   # a stand-in world counts exactly
        assert math.hypot(state.x - body.x, state.y - body.y) < 0.005
        assert abs(state.th - body.th) < 0.005
    finally:
        base.close()


def test_bumpers_from_dio_reports():
    world = BoxWorld()
    base, emulator, sim, clock = lockstep_pair(world)
    try:
        tick(base, sim, clock)
        world.bumpers = 1
        tick(base, sim, clock)
        assert base.read_state().bumpers == 1 << 6
        world.bumpers = 2
        tick(base, sim, clock)
        assert base.read_state().bumpers == 1 << 10
        world.bumpers = 0
        tick(base, sim, clock)
        assert base.read_state().bumpers == 0
    finally:
        base.close()


def test_link_goes_down_when_reports_stop_and_nothing_resumes():
    base, emulator, sim, clock = lockstep_pair()
    try:
        tick(base, sim, clock)
        base.command(0.3, 0.0)
        tick(base, sim, clock)
        emulator.muted = True
        for _ in range(6):
            base.command(0.3, 0.0)                      # a caller that does not look
            tick(base, sim, clock)
        assert not base.read_state().link_up
        for _ in range(12):
            tick(base, sim, clock)
        restarts = [c for _, c in emulator.controller.commands if c == p.ReportRequest(100_000, 3)]
        assert len(restarts) >= 2                          # the start sequence was sent again
        assert base.read_state().extra["command"] == (0.0, 0.0)
        emulator.muted = False
        tick(base, sim, clock)
        assert base.read_state().link_up
        assert all(c.velocity == 0 for _, c in set_dirs(emulator, since=clock.now() - 0.1))
    finally:
        base.close()


# --------------------------------------------------------------------------- pure parts

def make_unopened(**kw):
    return RFlexBase(PERSES.limits, "loop://", clock=SimClock(), **kw)


def motor(axis, position, velocity=0):
    return p.MotorReport(0, 0, axis, position, velocity, 0, 0)


def test_odometry_only_after_both_axes_are_fresh():
    base = make_unopened()
    base._apply_report(motor(0, 0))
    base._apply_report(motor(1, 0))                         # baseline
    base._apply_report(motor(0, round(DIST_CONV)))          # 1 m, rotation not yet fresh
    base._apply_report(motor(0, round(2 * DIST_CONV)))
    assert base.read_state().x == 0.0
    base._apply_report(motor(1, round(ANGLE_CONV * math.pi / 2)))
    state = base.read_state()
    assert state.th == pytest.approx(math.pi / 2)
    # 2 m along the mid-step heading (pi/4).
    assert (state.x, state.y) == pytest.approx((2 * math.cos(math.pi / 4), 2 * math.sin(math.pi / 4)), abs=1e-5)


def test_profile_factors_are_used():
    base = make_unopened(dist_conv=103000.0, angle_conv=35000.0)
    base._apply_report(motor(0, 0, velocity=51500))
    base._apply_report(motor(1, 0, velocity=-17500))
    state = base.read_state()
    assert (state.v, state.w) == pytest.approx((0.5, -0.5))
    assert PERSES.base.options == {"dist_conv": DIST_CONV, "angle_conv": ANGLE_CONV}


def test_sonar_reports_map_wire_ids_to_profile_indices():
    base = make_unopened()
    base._apply_report(p.SonarReport(0, 0, ((96, 1476), (3, 2952), (200, 100), (17, p.SONAR_NO_ECHO))))
    sonar = base.read_state().sonar
    assert sonar[24] == 1.0 and sonar[3] == 2.0 and sonar[5] == math.inf
    assert sum(math.isfinite(r) for r in sonar) == 2                # unknown id 200 ignored


def test_a_whole_ring_in_profile_order_reads_as_the_same_ring_in_any_order():
    # the one-pass path (every sonar, in the order the controller sends them) and the
    # reading-by-reading path give the same ring
    raws = [(97 * k) % 4000 if k % 5 else p.SONAR_NO_ECHO for k in range(p.SONAR_COUNT)]
    readings = tuple(zip(p.SONAR_WIRE_IDS, raws))
    in_order, shuffled = make_unopened(), make_unopened()
    in_order._apply_report(p.SonarReport(0, 0, readings))
    shuffled._apply_report(p.SonarReport(0, 0, readings[::-1]))
    ring = in_order.read_state().sonar
    assert ring == shuffled.read_state().sonar
    assert list(ring) == [p.sonar_metres(raw) for raw in raws]


def test_unknown_option_and_bad_factor_are_clear_errors():
    with pytest.raises(ProfileError, match="unknown option.*dist_cov.*allowed"):
        make_unopened(dist_cov=1.0)
    with pytest.raises(ProfileError, match="angle_conv = 0"):
        make_unopened(angle_conv=0)


def test_open_on_a_missing_port_names_it():
    base = RFlexBase(PERSES.limits, "/dev/does-not-exist-rflex")
    with pytest.raises(LinkError, match="does-not-exist-rflex"):
        base.open()


def test_command_before_open_is_refused():
    with pytest.raises(LinkError, match="not open"):
        make_unopened().command(0.1, 0.0)


def test_perses_in_simulation_speaks_rflex_over_a_pty():
    from robots.hardware import open_hardware

    hardware = open_hardware("perses", fast=True)
    try:
        assert isinstance(hardware.base, RFlexBase)
        assert hardware.base.url.startswith("/dev/pts/")
        for _ in range(3):
            hardware.clock.advance(0.1)
            hardware.sense()
        assert hardware.base.read_state().link_up
    finally:
        hardware.close()


def test_for_profile_takes_baud_and_factors_from_the_profile():
    base = RFlexBase.for_profile(PERSES, "loop://")
    assert (base.baud, base.dist_conv, base.angle_conv) == (115200, DIST_CONV, ANGLE_CONV)
    assert base.accel == PERSES.limits.max_accel
