"""The CANopen driver against the emulated drives on python-can's virtual bus.

Lock-step (simulated clock) for behaviour and determinism; real time for the start-up variants
and for the time from each fault to the zero command, which is measured and printed (run with
-s to see it), never asserted against a tight bound.
"""
from __future__ import annotations

import math
import re
import time
from dataclasses import replace

import can
import pytest

from robots.base import base_classes
from robots.canopen import protocol as p
from robots.canopen.driver import CanOpenBase, StartupError
from robots.canopen.emulator import CanOpenEmulator
from robots.clock import RealClock, SimClock
from robots.profile import load_profile
from robots.sim.simulation import Simulation

ARGOS = load_profile("argos")
S = p.State402


def wait_until(predicate, timeout=3.0, step=0.005):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(step)
    return predicate()


@pytest.fixture
def fast():
    clock = SimClock()
    simulation = Simulation(ARGOS, None, 0, clock)
    base = CanOpenBase.for_simulation(ARGOS, simulation, clock)
    base.open()

    def tick(dt=0.1):
        simulation.advance(clock.advance(dt))
        base.poll()
    yield base, simulation, clock, tick
    base.close()


def real_pair(**drive_knobs):
    """A real-time emulator standing alone (its thread steps the world) and an unopened driver."""
    clock = RealClock()
    simulation = Simulation(ARGOS, None, 0, clock)
    emulator = CanOpenEmulator.for_profile(ARGOS, simulation.world, clock=clock,
                                           boot_delays=drive_knobs.pop("boot_delays", None))
    for node, knobs in drive_knobs.get("drives", {}).items():
        for key, value in knobs.items():
            setattr(emulator.drives[node], key, value)
    emulator.attach(simulation)
    emulator.start_clock(simulation)
    config = replace(emulator.config, **drive_knobs.get("config", {}))
    base = CanOpenBase(ARGOS.limits, f"virtual:{emulator.channel}", clock=clock, config=config)
    return base, emulator


@pytest.fixture
def realtime():
    made = []

    def make(**knobs):
        base, emulator = real_pair(**knobs)
        made.append((base, emulator))
        return base, emulator
    yield make
    for base, emulator in made:
        base.close()
        emulator.close()


def first_zero_after(drive, t0, cw=None):
    """Monotonic time of the first RPDO after t0 with target 0 (and controlword cw, if given)."""
    for t, word, target in list(drive.rpdo_log):
        if t >= t0 and target == 0 and (cw is None or word == cw):
            return t
    return None


# -- start-up -----------------------------------------------------------------------------------
def test_entry_point_and_start_up_in_lock_step(fast):
    base, simulation, clock, tick = fast
    assert base_classes()["canopen"] is CanOpenBase
    emulator = base.emulator
    for drive in emulator.drives.values():
        assert drive.state is S.OPERATION_ENABLED and drive.mode == 3
        assert drive.nmt_state is p.NodeState.OPERATIONAL
        store = drive.node.data_store
        assert int.from_bytes(store[0x1A00][1], "little") == 0x60410010      # the host's mapping
        assert int.from_bytes(store[0x1600][2], "little") == 0x60FF0020
        assert int.from_bytes(store[0x1016][1], "little") == 0x007F012C      # host node 127, 300 ms
        assert store[0x6007][0] == b"\x03\x00"                                # quick stop on loss
    tick()
    state = base.read_state()
    assert state.link_up and state.motors_enabled and state.extra["fault"] == ""
    assert state.extra["statusword"] == {1: 0x1637, 2: 0x1637}                # OE, at rest
    assert len(state.sonar) == 8


def test_driving_moves_the_body_and_odometry_follows(fast):
    base, simulation, clock, tick = fast
    body = simulation.world.body
    for _ in range(30):
        base.command(0.4, 0.3)
        tick()
    state = base.read_state()
    assert state.v == pytest.approx(0.4, abs=0.01) and state.w == pytest.approx(0.3, abs=0.01)
    assert (state.x, state.y) == pytest.approx((body.x, body.y), abs=0.02)
    assert math.remainder(state.th - body.th, 2 * math.pi) == pytest.approx(0.0, abs=0.02)
    left, right = base.emulator.drives[1], base.emulator.drives[2]
    assert left.target > 0 > right.target          # mirrored right motor, turning left


def run_trace(seed_commands):
    clock = SimClock()
    simulation = Simulation(ARGOS, None, 0, clock)
    base = CanOpenBase.for_simulation(ARGOS, simulation, clock)
    base.open()
    out = []
    try:
        for i in range(60):
            simulation.advance(clock.advance(0.1))
            base.poll()
            s = base.read_state()
            out.append((s.t, s.x, s.y, s.th, s.v, s.w, s.sonar, s.link_up))
            base.command(*seed_commands(i))
    finally:
        base.close()
    return out


def test_fast_runs_are_deterministic():
    commands = lambda i: (0.3 * math.sin(i / 7), 0.5 * math.cos(i / 5))   # noqa: E731
    first, second = run_trace(commands), run_trace(commands)
    assert first == second
    assert len({row[1:4] for row in first}) > 40          # it did move


def test_host_watchdog_zeroes_the_targets_in_sim_time(fast):
    base, simulation, clock, tick = fast
    t_last = clock.now()
    base.command(0.3, 0.0)
    tick()
    assert base.emulator.drives[1].target > 0
    while base.emulator.drives[1].target != 0:
        tick(0.05)
        assert clock.now() - t_last < 1.0
    waited = clock.now() - t_last
    print(f"\nwatchdog (lock-step): zero {waited:.2f} s of sim time after the last command "
          f"(timeout 0.15 s; checked at each tick)")
    assert base.stats["watchdog_stops"] == 1 and base.emulator.drives[2].target == 0
    assert base.read_state().link_up                      # not a fault: the next command moves
    base.command(0.2, 0.0)
    assert base.emulator.drives[1].target > 0


def test_the_drives_quick_stop_by_themselves_when_the_host_stops(fast):
    base, simulation, clock, tick = fast
    base.command(0.3, 0.0)
    for _ in range(10):
        base.command(0.3, 0.0)
        tick()
    simulation.advance(clock.advance(0.6))       # the host hangs: no heartbeat, no poll
    drives = base.emulator.drives.values()
    assert all(0x8130 in d.injected for d in drives)
    assert all(d.state in (S.QUICK_STOP_ACTIVE, S.SWITCH_ON_DISABLED) for d in drives)
    base.poll()
    state = base.read_state()
    assert not state.link_up and "0x8130" in state.extra["fault"]
    assert "heartbeat" in state.extra["fault"]


def logged_session(path, commands) -> list[str]:
    """The candump log of a simulated ARGOS session driven by `commands` ((v, w) per 0.1 s)."""
    clock = SimClock()
    simulation = Simulation(ARGOS, None, 0, clock)
    base = CanOpenBase.for_simulation(ARGOS, simulation, clock)
    base.can_log_path = str(path)
    base.open()
    for v, w in commands:
        base.command(v, w)
        simulation.advance(clock.advance(0.1))
        base.poll()
    base.close()
    return path.read_text().splitlines()


def test_candump_log_of_a_session(tmp_path):
    path = tmp_path / "session.log"
    lines = logged_session(path, [(0.2, 0.0)] * 5)
    pattern = re.compile(r"^\(\d+\.\d{6}\) \S+ [0-9A-F]{3}#[0-9A-F]*$")
    assert lines and all(pattern.match(line) for line in lines), lines[:3]
    frames = [line.split()[2] for line in lines]
    # canopen's SDO client put on the wire exactly the golden frames of the protocol notes
    for golden in ("000#8200", "701#00", "702#00", "601#2F60600003000000", "581#6060600000000000",
                   "601#4041600000000000", "601#2B40600006000000", "000#0100", "080#", "77F#05"):
        assert golden in frames, golden
    assert any(f.startswith("201#0F00") for f in frames) and any(f.startswith("181#3706") for f in frames)
    read_back = list(can.CanutilsLogReader(path))            # python-can reads it as candump -l
    assert len(read_back) == len(lines)


# -- start-up variants (real time) ----------------------------------------------------------------
def test_start_up_in_real_time_and_with_a_slow_drive(realtime):
    base, emulator = realtime(drives={2: {"sdo_delay": 0.01}})
    t0 = time.monotonic()
    base.open()
    took = time.monotonic() - t0
    print(f"\nstart-up with a drive answering SDO 10 ms late: {took:.2f} s "
          f"(configure + enable {base.startup_time:.2f} s)")
    assert base.read_state().link_up
    assert all(d.state is S.OPERATION_ENABLED for d in emulator.drives.values())
    assert wait_until(lambda: base.stats["cycles"] > 5)


def test_a_refused_write_names_node_object_and_abort_code(realtime):
    base, emulator = realtime(drives={2: {"refuse": {(0x6060, 0): 0x06010002}}})
    with pytest.raises(StartupError) as err:
        base.open()
    text = str(err.value)
    for words in ("node 2 (right wheel)", "0x6060:00", "modes of operation", "0x06010002",
                  "attempt to write a read-only object"):
        assert words in text, text
    assert emulator.drives[2].state is S.SWITCH_ON_DISABLED


def test_a_drive_too_slow_for_the_sdo_timeout(realtime):
    base, emulator = realtime(drives={1: {"sdo_delay": 0.4}}, config={"sdo_timeout": 0.05})
    with pytest.raises(StartupError, match=r"node 1 \(left wheel\): SDO read 0x1000:00 \(device type\) "
                                           r"got no answer within 0.05 s"):
        base.open()


def test_a_drive_that_boots_late(realtime):
    base, emulator = realtime(boot_delays={2: 0.4})
    t0 = time.monotonic()
    base.open()
    print(f"\nstart-up with the right drive booting 0.4 s late: {time.monotonic() - t0:.2f} s")
    assert base.read_state().link_up


def test_a_drive_that_never_boots(realtime):
    base, emulator = realtime(boot_delays={2: None}, config={"boot_timeout": 0.3})
    with pytest.raises(StartupError, match=r"node 2 \(right wheel\) sent no boot-up \(0x702 data 00\) "
                                           r"within 0.3 s after NMT reset communication"):
        base.open()


def test_a_drive_already_in_fault_is_not_reset_silently(realtime):
    base, emulator = realtime()
    emulator.inject_fault(1, 0x4210)
    with pytest.raises(StartupError, match=r"node 1 \(left wheel\) is in Fault .*0x4210.*reset_faults"):
        base.open()
    assert emulator.drives[1].state is S.FAULT


# -- faults (real time; time from fault to zero command measured) ---------------------------------------
def opened(realtime):
    base, emulator = realtime()
    base.open()
    for _ in range(10):
        base.command(0.3, 0.0)
        time.sleep(0.02)
    assert emulator.drives[1].target > 0
    return base, emulator


def report(what, t0, drive, cw=None):
    """Wait for the zero command at `drive`, print how long after `t0` it arrived."""
    assert wait_until(lambda: first_zero_after(drive, t0, cw) is not None), f"{what}: no zero command"
    t_zero = first_zero_after(drive, t0, cw)
    print(f"\n{what}: fault -> zero command on the other drive in {(t_zero - t0) * 1000:.1f} ms")


def test_emcy_over_current_stops_both_wheels_until_reset_and_activated(realtime):
    base, emulator = opened(realtime)
    t0 = time.monotonic()
    emulator.inject_fault(1, 0x2310)
    assert wait_until(lambda: not base.read_state().link_up)
    report("EMCY 0x2310", t0, emulator.drives[2], p.Cw.QUICK_STOP)
    fault = base.read_state().extra["fault"]
    assert "node 1 (left wheel)" in fault and "0x2310" in fault and "over-current" in fault
    assert wait_until(lambda: emulator.drives[1].state is S.FAULT)
    base.command(0.3, 0.0)                                 # ignored: nothing moves by itself
    time.sleep(0.1)
    assert emulator.drives[2].target == 0 and emulator.drives[1].target == 0
    with pytest.raises(StartupError, match="reset_faults"):
        base.activate()
    with pytest.raises(StartupError, match="motion is commanded"):
        base.reset_faults()                                # 0.3 m/s was asked a moment ago
    base.command(0.0, 0.0)
    assert base.reset_faults() == [1]
    base.activate()
    assert base.read_state().link_up and base.fault is None
    base.command(0.3, 0.0)
    assert wait_until(lambda: emulator.drives[1].target > 0)


def test_the_fault_bit_alone_stops_both_wheels(realtime):
    base, emulator = opened(realtime)
    t0 = time.monotonic()
    with emulator.lock:
        emulator.drives[2].state = S.FAULT            # no EMCY: only the statusword tells
    assert wait_until(lambda: not base.read_state().link_up)
    report("statusword fault bit", t0, emulator.drives[1], p.Cw.QUICK_STOP)
    assert "node 2 (right wheel): statusword 0x0218 has the fault bit" in base.read_state().extra["fault"]


def test_heartbeat_loss_stops_the_other_wheel_and_reports_link_down(realtime):
    base, emulator = opened(realtime)
    t0 = time.monotonic()
    emulator.power_off(2)
    assert wait_until(lambda: not base.read_state().link_up, timeout=2.0)
    report("heartbeat loss (time-out 300 ms)", t0, emulator.drives[1], p.Cw.QUICK_STOP)
    fault = base.read_state().extra["fault"]
    assert "node 2 (right wheel): no heartbeat" in fault and "stopped the left wheel" in fault
    emulator.power_on(2)                                # it comes back: still nothing moves ...
    time.sleep(0.2)
    base.command(0.3, 0.0)
    assert emulator.drives[1].target == 0
    base.activate()                                     # ... until motion is activated anew
    base.command(0.3, 0.0)
    assert wait_until(lambda: emulator.drives[2].target < 0)


@pytest.mark.parametrize("state", ["error-passive", "bus-off"])
def test_bus_error_states_are_reported(realtime, state):
    base, emulator = opened(realtime)
    t0 = time.monotonic()
    emulator.bus_error(state)
    assert wait_until(lambda: not base.read_state().link_up)
    report(f"bus {state}", t0, emulator.drives[1], p.Cw.QUICK_STOP)
    assert f"CAN bus {state}" in base.read_state().extra["fault"] and base.bus_state == state


def test_host_watchdog_in_real_time(realtime):
    base, emulator = opened(realtime)
    base.command(0.3, 0.0)
    t_last = time.monotonic()
    report("host watchdog (0.15 s after the last command)", t_last, emulator.drives[1])
    assert base.read_state().link_up and base.stats["watchdog_stops"] == 1


def test_pushing_against_a_person_trips_over_current_and_stops(standing_person):
    clock = SimClock()
    simulation = Simulation(ARGOS, standing_person(0.0, 0.0), 0, clock)   # 0.75 m ahead
    base = CanOpenBase.for_simulation(ARGOS, simulation, clock)
    base.open()
    try:
        for _ in range(60):
            base.command(0.3, 0.0)          # L0 obeys; the safety arbiter lives in L1
            simulation.advance(clock.advance(0.1))
            base.poll()
            if not base.read_state().link_up:
                break
        state = base.read_state()
        assert simulation.world.body.stalled or simulation.world.body.v == 0.0
        assert not state.link_up and "EMCY 0x2310 over-current" in state.extra["fault"]
        drives = base.emulator.drives
        assert all(d.target == 0 for d in drives.values())
        assert any(d.state in (S.FAULT, S.FAULT_REACTION_ACTIVE) for d in drives.values())
    finally:
        base.close()


def test_a_wheel_that_cannot_follow_raises_following_error(fast):
    base, simulation, clock, tick = fast
    body = simulation.world.body
    body.limits = replace(body.limits, max_accel=0.01)       # the body barely answers the wheels
    for _ in range(40):
        base.command(0.5, 0.0)
        tick()
        if not base.read_state().link_up:
            break
    fault = base.read_state().extra["fault"]
    assert "EMCY 0x8611 following error" in fault, fault
    assert all(d.target == 0 for d in base.emulator.drives.values())


def test_in_lock_step_the_emulator_handles_frames_on_the_drivers_thread(fast):
    """No notifier thread in the in-process emulator: the driver's `send` hands each frame over
    (`LockStep.deliver` -> `CanOpenEmulator._pump`), so it is handled before `send` returns."""
    import threading
    base, simulation, clock, tick = fast
    emulator = base.emulator
    assert emulator.network.notifier is None and base.lockstep.pump == emulator._pump
    handled = []
    emulator.network.subscribe(p.SYNC_ID, lambda *frame: handled.append(threading.current_thread()))
    tick()
    assert handled and all(thread is threading.current_thread() for thread in handled)
    assert base.lockstep.to_device.backlog() == 0


def test_in_lock_step_the_driver_reads_the_bus_on_its_own_thread():
    """No Notifier thread on the host side either: each frame the emulator sends is handled
    on the caller's thread, after the driver's send (an SDO finds its answer queued at once)
    or in poll()."""
    import threading
    before = set(threading.enumerate())
    clock = SimClock()
    simulation = Simulation(ARGOS, None, 0, clock)
    base = CanOpenBase.for_simulation(ARGOS, simulation, clock)
    base.open()
    try:
        started = [t.name for t in set(threading.enumerate()) - before if t.is_alive()]
        assert not [name for name in started if "Notifier" in name], started
        assert base.network.notifier is None and base.receiver is not None
        handled = []
        base.network.subscribe(p.tpdo_id(1, 1), lambda *frame: handled.append(threading.current_thread()))
        simulation.advance(clock.advance(0.1))
        base.poll()
        assert handled and all(thread is threading.current_thread() for thread in handled)
        t0 = time.monotonic()
        assert p.state_of(base._sdo_read(1, p.STATUSWORD, 0, "statusword")) is S.OPERATION_ENABLED
        assert time.monotonic() - t0 < base.config.sdo_timeout       # answered, not timed out
        assert base.lockstep.to_host.backlog() == 0
    finally:
        base.close()


def test_a_lock_step_session_log_is_in_bus_order_and_the_same_every_run(tmp_path):
    """Read on the driver's thread, the emulator's frames are logged when they are on the bus
    (a Notifier thread logged them whenever it got to them): the log's stamps never go back,
    and two runs log the same frames in the same order."""
    def session(path) -> list[list[str]]:
        commands = [(0.2 if i < 12 else 0.0, 0.1) for i in range(20)]
        return [line.split() for line in logged_session(path, commands)]
    first, second = session(tmp_path / "first.log"), session(tmp_path / "second.log")
    stamps = [float(row[0].strip("()")) for row in first]
    assert stamps == sorted(stamps)
    assert [row[2] for row in first] == [row[2] for row in second]
    assert len(first) > 300 and any(row[2].startswith("181#") for row in first)


def test_in_lock_step_a_bus_gone_is_a_link_fault_and_the_drives_stop_by_themselves(fast):
    """Read on the driver's thread, a bus that fails (an adapter unplugged) still reaches the
    listeners' on_error: a link fault, not an exception out of poll(); the drives, no longer
    hearing the host, quick-stop by themselves."""
    base, simulation, clock, tick = fast
    for _ in range(5):
        base.command(0.3, 0.0)
        tick()
    base.network.bus.bus.shutdown()
    base.command(0.3, 0.0)
    tick(0.4)                                     # longer than the drives' host heartbeat time-out
    state = base.read_state()
    assert not state.link_up and state.extra["fault_device"].startswith("CAN link"), state.extra
    assert all(d.state is S.QUICK_STOP_ACTIVE for d in base.emulator.drives.values())
