"""The stops a driver sends at once, not with its next cycle (issue 24 point 8): each is caught
here when it is removed, by a bound in emulator time, not wall time. In lock-step (simulated
clock) a write is applied by the emulated controller before it returns, so "at once" means: at
the same emulator time, before the next poll. Where the driver acts in real time on a receiving
thread (a CAN fault), "at once" means before the driver's next control cycle, in the order the
driver handled its frames.

- rFLEX `stop()`: zero on both axes at once (the 10 Hz resend would carry it 0.1 s later);
- rFLEX start sequence: zero on both axes after the brake release, even on a controller whose
  MOT_SET_DEFAULTS leaves the velocity alone (rflex.md's start sequence has it; the notes do not
  say that defaults stop the axes);
- CANopen `stop()` and watchdog: target 0 to both drives at once (the next cycle would carry it);
- CANopen fault: quick stop to both drives from the handler that saw the fault, before the
  next cycle's RPDOs.
"""
from __future__ import annotations

import threading
from dataclasses import replace

import pytest

from robots.clock import SimClock
from robots.profile import load_profile
from robots.sim.simulation import Simulation
from tests.faults.conftest import argos_drives_in_real_time

SPEED = 0.3


def lockstep(robot: str, driver_class):
    profile = load_profile(robot)
    clock = SimClock()
    simulation = Simulation(profile, None, 0, clock)
    base = driver_class.for_simulation(profile, simulation, clock)
    return base, simulation, clock


def step(base, simulation, clock, dt: float, v: float | None = None) -> None:
    if v is not None:
        base.command(v, 0.0)
    simulation.advance(clock.advance(dt))
    base.poll()


# -- rFLEX ------------------------------------------------------------------------------------------
@pytest.fixture
def rflex():
    from robots.rflex.driver import RFlexBase
    base, simulation, clock = lockstep("perses", RFlexBase)
    yield base, base._emulator.controller, simulation, clock
    base.close()


def test_rflex_stop_reaches_the_controller_at_once(rflex):
    base, controller, simulation, clock = rflex
    base.open()
    for _ in range(10):
        step(base, simulation, clock, 0.1, SPEED)
    assert controller.axes[0].target > 0
    base.stop()                                        # no poll, no time passes
    assert controller.axes[0].target == 0 and controller.axes[1].target == 0
    assert controller.commands[-1][0] == simulation.world.t


def test_rflex_start_sequence_zeroes_axes_a_previous_host_left_moving(rflex):
    base, controller, simulation, clock = rflex
    controller.defaults_stop_axes = False              # MOT_SET_DEFAULTS leaves the velocity
    controller.brake = False
    controller.axes[0].target = 0.4 * base.dist_conv   # a host before us left it driving
    controller.axes[1].target = 0.2 * base.angle_conv
    base.open()                                        # the start sequence, no time passes
    assert controller.axes[0].target == 0 and controller.axes[1].target == 0
    assert not controller.brake


# -- CANopen ----------------------------------------------------------------------------------------
@pytest.fixture
def canopen():
    from robots.canopen.driver import CanOpenBase
    base, simulation, clock = lockstep("argos", CanOpenBase)
    base.open()
    for _ in range(10):
        step(base, simulation, clock, 0.1, SPEED)
    drives = base.emulator.drives
    assert drives[1].target > 0 and drives[2].target < 0
    yield base, drives, simulation, clock
    base.close()


def test_canopen_stop_reaches_both_drives_at_once(canopen):
    base, drives, simulation, clock = canopen
    base.stop()                                        # no poll, no time passes
    assert drives[1].target == 0 and drives[2].target == 0


def test_canopen_watchdog_zero_reaches_both_drives_in_the_poll_that_finds_it(canopen):
    base, drives, simulation, clock = canopen
    for _ in range(20):                                # the tick loop hangs: polls, no commands
        step(base, simulation, clock, base.config.sync_period)
        if base.stats["watchdog_stops"]:
            break
    assert base.stats["watchdog_stops"] == 1
    assert drives[1].target == 0 and drives[2].target == 0


def test_canopen_fault_quick_stop_goes_out_before_the_next_cycle():
    """Real time: the EMCY is handled on the receiving thread, which also runs each control
    cycle (TPDO2 of both drives in, RPDOs out), so what it sends in between is in order."""
    from robots.canopen import protocol as p
    from robots.canopen.driver import CanOpenBase
    from tests.faults.conftest import wait
    argos, clock, emulator = argos_drives_in_real_time()
    base = CanOpenBase(argos.limits, f"virtual:{emulator.channel}", clock=clock, config=emulator.config)
    order: list[tuple[str, int, int]] = []
    lock = threading.Lock()
    send, on_emcy, on_tpdo2 = base._send, base._on_emcy, base._on_tpdo2

    def sending(can_id, data, *rest):
        if can_id & 0x780 == 0x200:                    # RPDO1: (controlword, target)
            with lock:
                order.append(("rpdo", can_id & 0x7F, int.from_bytes(bytes(data[:2]), "little")))
        return send(can_id, data, *rest)

    def marked(name, handler):
        def handle(can_id, data, timestamp):
            with lock:                                 # (an EMCY with its error code)
                order.append((name, can_id & 0x7F, int.from_bytes(bytes(data[:2]), "little")))
            return handler(can_id, data, timestamp)
        return handle
    base._send = sending
    base._on_emcy, base._on_tpdo2 = marked("emcy", on_emcy), marked("tpdo2", on_tpdo2)
    try:
        base.open()
        for _ in range(10):
            base.command(SPEED, 0.0)
            wait(0.05)
        emulator.inject_fault(1, 0x2310)
        wait(0.3)
        with lock:
            seen = list(order)
        first_emcy = next(i for i, entry in enumerate(seen) if entry[:3:2] == ("emcy", 0x2310))
        after = seen[first_emcy + 1:]
        next_cycle = next(i for i, entry in enumerate(after) if entry[0] == "tpdo2")
        quick_stops = {node for kind, node, word in after[:next_cycle]
                       if kind == "rpdo" and word == p.Cw.QUICK_STOP}
        assert quick_stops == {1, 2}, after[:next_cycle + 2]
    finally:
        base.close()
        emulator.close()


def test_canopen_after_a_fault_every_cycle_keeps_quick_stop_and_zero():
    """A drive without 0x605A whose own quick stop stays in Quick Stop Active (option 6, as
    some makers ship): there an enable-operation controlword drives again (CiA 402 transition
    16), so every RPDO after a fault must carry quick stop and target 0, not the old command."""
    from robots.canopen.driver import CanOpenBase
    base, simulation, clock = lockstep("argos", CanOpenBase)
    for drive in base.emulator.drives.values():
        drive.remove_objects(0x605A)
        drive.quick_stop_default = 6
    base.open()
    try:
        for _ in range(10):
            step(base, simulation, clock, 0.1, SPEED)
        base.emulator.inject_fault(1, 0x2310)
        for _ in range(20):                             # 2 s: the tick loop commands on
            step(base, simulation, clock, 0.1, SPEED)
        right = base.emulator.drives[2]
        assert right.state.value == "quick stop active" and right.target == 0
        assert simulation.world.body.v == 0.0 and simulation.world.body.w == 0.0
    finally:
        base.close()
