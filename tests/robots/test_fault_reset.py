"""A drive fault's reset on the serial bases (issue 24 point 3), against their emulators in
lock-step: P2OS re-enables its motors (ENABLE 1) once the e-stop is released, rFLEX releases its
brake; each only with the option `reset_faults`, never while motion is commanded, never while
the controller still reports the cause, and the robot stays still until commanded anew."""
from __future__ import annotations

from dataclasses import replace

import pytest

from robots.clock import SimClock
from robots.exceptions import FaultResetError
from robots.p2os.driver import P2OSBase
from robots.profile import load_profile
from robots.rflex.driver import RFlexBase
from robots.sim.simulation import Simulation

DRIVERS = {"horos": P2OSBase, "perses": RFlexBase}


def opened(robot: str, reset_faults: bool = True):
    profile = load_profile(robot)
    profile = replace(profile, base=replace(profile.base, options={**profile.base.options,
                                                                   "reset_faults": reset_faults}))
    clock = SimClock()
    simulation = Simulation(profile, None, 0, clock)
    base = DRIVERS[robot].for_simulation(profile, simulation, clock)
    base.open()
    return base, simulation, clock


def emulator_of(base):
    return getattr(base, "emulator", None) or base._emulator


def run_for(base, simulation, clock, seconds: float, v: float = 0.0, w: float = 0.0) -> None:
    for _ in range(round(seconds / 0.1)):
        base.command(v, w)
        simulation.advance(clock.advance(0.1))
        base.poll()


def faulted(robot: str, **kw):
    """Driving at 0.3 m/s, then the e-stop pressed: the driver has latched a drive fault."""
    base, simulation, clock = opened(robot, **kw)
    run_for(base, simulation, clock, 1.5, v=0.3)
    assert simulation.world.body.v > 0.2
    emulator_of(base).press_estop()
    run_for(base, simulation, clock, 1.5, v=0.3)          # the caller still asks for motion
    assert base.drive_fault is not None and not base.read_state().link_up
    return base, simulation, clock


@pytest.mark.parametrize("robot", DRIVERS)
def test_a_reset_is_refused_while_motion_is_commanded(robot):
    base, simulation, clock = faulted(robot)
    try:
        emulator_of(base).press_estop(False)
        run_for(base, simulation, clock, 0.3, v=0.3)
        assert not base.fault_resettable()
        with pytest.raises(FaultResetError, match="fault reset refused: motion is commanded"):
            base.reset_faults()
        assert base.drive_fault is not None and simulation.world.body.v == 0.0
    finally:
        base.close()


@pytest.mark.parametrize("robot", DRIVERS)
def test_a_reset_clears_the_fault_and_nothing_moves_until_commanded_anew(robot):
    base, simulation, clock = faulted(robot)
    try:
        emulator_of(base).press_estop(False)
        run_for(base, simulation, clock, 0.3)               # zero commanded: the watchdog time
        assert base.fault_resettable() and base.read_state().extra["fault_resettable"]
        assert base.reset_faults() == [base.read_state().extra["fault_device"]]
        run_for(base, simulation, clock, 1.0)
        state = base.read_state()
        assert base.drive_fault is None and state.link_up and "fault" not in state.extra
        assert simulation.world.body.v == 0.0               # reset, and still standing
        run_for(base, simulation, clock, 1.0, v=0.3)        # commanded anew: it drives
        assert simulation.world.body.v > 0.2
    finally:
        base.close()


@pytest.mark.parametrize("robot", DRIVERS)
def test_a_reset_while_the_estop_is_held_leaves_the_fault_latched(robot):
    base, simulation, clock = faulted(robot)
    try:
        run_for(base, simulation, clock, 0.3)
        if robot == "horos":                # P2OS reports its e-stop: the reset is refused
            assert not base.fault_resettable()
            with pytest.raises(FaultResetError, match="e-stop is still pressed"):
                base.reset_faults()
        else:                               # rFLEX does not: the controller keeps its brake
            base.reset_faults()
            run_for(base, simulation, clock, 0.5)
            assert base.fault_reset.failed == 1 and "kept its brake set" in base.fault_reset.last_failure
            assert not base.fault_resettable()             # not again before the retry time
        run_for(base, simulation, clock, 1.0, v=0.3)
        assert base.drive_fault is not None and simulation.world.body.v == 0.0
    finally:
        base.close()


def test_p2os_motors_switched_off_are_reset_by_enable():
    base, simulation, clock = opened("horos")
    try:
        run_for(base, simulation, clock, 1.5, v=0.3)
        emulator_of(base).switch_motors_off()
        run_for(base, simulation, clock, 0.5)
        assert base.drive_fault["meaning"].startswith("motors disabled by the controller")
        assert base.reset_faults() == ["P2OS motors"]
        run_for(base, simulation, clock, 0.5)
        assert base.drive_fault is None and base.read_state().motors_enabled
    finally:
        base.close()


@pytest.mark.parametrize("robot", DRIVERS)
def test_without_the_option_no_reset(robot):
    base, simulation, clock = faulted(robot, reset_faults=False)
    try:
        emulator_of(base).press_estop(False)
        run_for(base, simulation, clock, 0.3)
        assert not base.fault_resettable()
        with pytest.raises(FaultResetError, match="option reset_faults is off"):
            base.reset_faults()
    finally:
        base.close()


@pytest.mark.parametrize("robot", DRIVERS)
def test_the_profile_option_is_checked(robot):
    driver = DRIVERS[robot]
    assert driver.profile_problems({"reset_faults": True}) == []
    problems = driver.profile_problems({"reset_faults": "yes"})
    assert problems == [("reset_faults", "reset_faults = 'yes' must be true or false")]


def test_p2os_started_with_its_estop_pressed_is_a_fault_until_released_and_reset():
    profile = load_profile("horos")
    profile = replace(profile, base=replace(profile.base, options={**profile.base.options,
                                                                   "reset_faults": True}))
    clock = SimClock()
    simulation = Simulation(profile, None, 0, clock)
    base = P2OSBase.for_simulation(profile, simulation, clock)
    base.emulator.press_estop()                          # pressed before we connect
    base.open()
    try:
        run_for(base, simulation, clock, 0.5)
        assert base.drive_fault["meaning"].startswith("e-stop pressed")
        assert not base.read_state().link_up and not base.fault_resettable()
        base.emulator.press_estop(False)
        run_for(base, simulation, clock, 0.3)
        assert base.reset_faults() == ["P2OS motors"]
        run_for(base, simulation, clock, 0.5)
        assert base.drive_fault is None and base.read_state().motors_enabled
    finally:
        base.close()
