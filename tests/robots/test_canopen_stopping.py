"""Stopping as a drive manual says: quick stop on the quick-stop ramp, standstill (or a bounded
time), then disable; 0x605C = 1 so that disable operation brakes. The emulated wheels roll on
when a drive lets go of them at speed (`COAST_DECEL`), so a stop that skips a step shows."""
from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from robots.canopen import protocol as p
from robots.canopen.driver import CanOpenBase
from robots.clock import SimClock
from robots.profile import load_profile
from robots.sim.simulation import Simulation
from tests.processes import faulthandler_env, finish

ARGOS = load_profile("argos")
S = p.State402
REPO = Path(__file__).resolve().parents[2]
SPEED = 0.4


@pytest.fixture
def moving():
    """The base in lock-step, driven straight at 0.4 m/s for 1.5 s (1.6 m free ahead)."""
    clock = SimClock()
    simulation = Simulation(ARGOS, None, 0, clock)
    base = CanOpenBase.for_simulation(ARGOS, simulation, clock)
    base.open()
    for _ in range(15):
        base.command(SPEED, 0.0)
        simulation.advance(clock.advance(0.1))
        base.poll()
    assert simulation.world.body.v == pytest.approx(SPEED, abs=0.01)
    yield base, simulation, clock
    base.close()


def place(body):
    return body.x, body.y


def distance(a, b):
    return ((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** 0.5


def words(drive, since):
    return [(t, w, speed) for t, w, speed in drive.cw_log if t >= since]


def test_close_quick_stops_waits_for_standstill_then_disables(moving):
    base, simulation, clock = moving
    body = simulation.world.body
    emulator = base.emulator
    start, t0 = place(body), clock.now()
    base.close()
    for drive in emulator.drives.values():
        assert drive.node.data_store[p.DISABLE_OPERATION_OPTION][0] == b"\x01\x00"   # 0x605C = 1
        assert drive.node.data_store[p.QUICK_STOP_OPTION][0] == b"\x02\x00"          # 0x605A = 2
        seq = [(w, speed) for _, w, speed in words(drive, t0)]
        assert [w for w, _ in seq] == [p.Cw.QUICK_STOP, p.Cw.SWITCH_ON, p.Cw.DISABLE_VOLTAGE], seq
        assert seq[0][1] == pytest.approx(SPEED, abs=0.02)        # quick stop at full speed
        assert seq[1][1] <= ARGOS.base.options.get("standstill_window", 0.01)   # disable at rest
        assert drive.state is S.SWITCH_ON_DISABLED
    assert body.v == 0.0
    travelled = distance(place(body), start)
    print(f"\nstopping distance from {SPEED} m/s: {travelled * 1000:.0f} mm")
    assert travelled < SPEED ** 2 / (2 * 0.5) + 0.02    # the body's own 0.5 m/s² limit, + a cycle
    record = base.stop_log[-1]
    assert record["standstill"] and record["why"] == "close"


def test_disable_operation_at_speed_without_0x605c_lets_the_wheels_roll_on(moving):
    """The emulator's side of it: the old way (target 0 and disable operation at once, 0x605C = 0)
    rolls on for metres; this is what the stop sequence avoids."""
    base, simulation, clock = moving
    body = simulation.world.body
    for drive in base.emulator.drives.values():
        drive.node.set_data(p.DISABLE_OPERATION_OPTION, 0, b"\x00\x00")
    start = place(body)
    with base._lock:
        base._enabled = False
        for node in base.nodes:
            base._send(*p.rpdo1(node, p.Cw.SWITCH_ON, 0))
    for _ in range(50):
        simulation.advance(clock.advance(0.1))
    rolled = distance(place(body), start)
    print(f"\nrolled on after disable operation with 0x605C = 0: {rolled * 1000:.0f} mm")
    assert rolled > 0.35                  # 0.4 m/s at 0.2 m/s² friction: 0.4 m


def test_a_fault_keeps_sync_and_odometry_going_while_the_robot_stops(moving):
    base, simulation, clock = moving
    body = simulation.world.body
    syncs = base.stats["syncs"]
    base.emulator.inject_fault(1, 0x2310)
    for _ in range(20):
        simulation.advance(clock.advance(0.1))
        base.poll()
    assert base.fault and "0x2310" in base.fault
    assert body.v == 0.0
    assert base.stats["syncs"] >= syncs + 19           # one per lock-step poll, fault or not
    state = base.read_state()
    assert (state.x, state.y) == pytest.approx((body.x, body.y), abs=0.005)


def test_closing_with_a_dead_drive_takes_a_bounded_time(moving):
    base, simulation, clock = moving
    emulator = base.emulator
    emulator.power_off(2)
    t0 = clock.now()
    base.close()
    print(f"\nclosing with the right drive dead took {clock.now() - t0:.2f} s of robot time")
    assert clock.now() - t0 <= 1.0          # the left one's quick stop; the right one is not waited for
    assert emulator.drives[1].state is S.SWITCH_ON_DISABLED


# -- every exit path of `interbot run` --------------------------------------------------------------
def frames(log: Path, can_id: str) -> list[str]:
    """Data of the frames with `can_id` in a candump -l log, in order."""
    pattern = re.compile(rf"^\(\S+\) \S+ {can_id}#([0-9A-F]*)$")
    return [m.group(1) for m in map(pattern.match, log.read_text().splitlines()) if m]


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_a_signal_ends_the_run_with_the_stop_sequence_on_the_bus(tmp_path, signum):
    log = tmp_path / "session.log"
    env = faulthandler_env(dict(os.environ, PYTHONPATH=str(REPO), INTERBOT_CAN_LOG=str(log)))
    process = subprocess.Popen(
        [sys.executable, "-m", "applications.cli", "run", "survey", "--robot", "argos", "--quiet",
         "--duration", "600", "--data", str(tmp_path / "answers.sqlite")],
        cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not (log.exists() and frames(log, "080")):
        time.sleep(0.1)                  # SYNC flows: the drives are enabled
    time.sleep(0.5)
    process.send_signal(signum)
    out, err = finish(process, timeout=60)
    assert process.returncode == 128 + signum, err
    for node in (1, 2):
        words = [int.from_bytes(bytes.fromhex(d[:4]), "little") for d in frames(log, f"20{node}")]
        tail = [w for i, w in enumerate(words) if i == 0 or w != words[i - 1]][-4:]
        assert tail[-3:] == [p.Cw.QUICK_STOP, p.Cw.SWITCH_ON, p.Cw.DISABLE_VOLTAGE], tail
    assert frames(log, "000")[-1] == "8000"          # then NMT pre-operational


def test_a_silent_sonar_board_is_a_fault_not_free_space(moving):
    base, simulation, clock = moving
    base.emulator.sonar_powered = False
    for _ in range(5):
        base.command(SPEED, 0.0)
        simulation.advance(clock.advance(0.1))
        base.poll()
    state = base.read_state()
    assert not state.link_up and "node 16 (sonar board): no ranges for" in base.fault
    assert state.extra["fault_device"] == "node 16 (sonar board)"
