"""The fault suite with the robot moving (issue 24 point 8): a commander drives each base at
20 Hz (twice the tick loop's rate), a fault is injected, and the test asserts that the stop reached
the robot end (as the robot end recorded it, with its arrival time) within 0.5 s.

One test per stop of each driver, arranged so that only that stop can deliver it in time (the
commander keeps commanding where a watchdog would otherwise stop the robot): removing any one
of the drivers' stops fails a test here. Covers P2OS (a scripted Pioneer on TCP), rFLEX (the
emulated controller on a pty) and CANopen (two emulated CiA 402 drives on a virtual bus)."""
from __future__ import annotations

import threading
import time
from dataclasses import replace

import pytest

from robots.profile import load_profile
from tests.faults.conftest import argos_drives_in_real_time

WITHIN = 0.5                  # s from the fault to the stop at the robot end (issue 24)
SPEED = 0.3                   # m/s the commander asks for


class Commander:
    """Commands (SPEED, 0) every 0.05 s on a thread of its own until `halt()` (a hung tick
    loop); twice the tick loop's rate, so a loaded machine does not starve it into the 0.15 s
    watchdog where a test wants another stop."""

    def __init__(self, base) -> None:
        self.base = base
        self._halt = threading.Event()
        self.halted_at: float | None = None
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._halt.is_set():
            try:
                self.base.command(SPEED, 0.0)
            except Exception:
                pass
            self._halt.wait(0.05)

    def halt(self) -> float:
        self._halt.set()
        self._thread.join(timeout=1.0)
        self.halted_at = time.monotonic()
        return self.halted_at


def wait_for(predicate, timeout: float = 5.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        found = predicate()
        if found:
            return found
        time.sleep(0.005)
    return predicate()


def assert_stopped_in_time(what: str, t_fault: float, t_stop: float | None) -> None:
    assert t_stop is not None, f"{what}: no stop reached the robot end"
    delay = t_stop - t_fault
    print(f"{what}: stop at the robot end {delay * 1000:.0f} ms after the fault")
    assert delay <= WITHIN, f"{what}: the stop came {delay:.2f} s after the fault"


# -- P2OS: the scripted Pioneer records each packet with its arrival time -----------------------

def p2os_vel(peer, conn: int | None = None):
    return [r for r in list(peer.received) if r.name.startswith("VEL ")
            and (conn is None or r.conn == conn)]


def p2os_first_zero_after(peer, t: float, conn: int | None = None):
    return next((r.t for r in p2os_vel(peer, conn) if r.t >= t and r.name == "VEL 0"), None)


@pytest.fixture
def p2os_moving(peer):
    from robots.p2os.driver import P2OSBase
    base = P2OSBase(load_profile("horos").limits, peer.url)
    base.open()
    commander = Commander(base)
    assert wait_for(lambda: any(r.name == "VEL 300" for r in p2os_vel(peer))), "never moved"
    yield base, commander
    commander.halt()
    base.close()


def test_p2os_a_hung_tick_loop_is_stopped_by_the_watchdog(peer, p2os_moving):
    base, commander = p2os_moving
    t0 = commander.halt()
    assert_stopped_in_time("P2OS watchdog", t0, wait_for(lambda: p2os_first_zero_after(peer, t0)))


@pytest.mark.parametrize("mode", ["silent", "garbage"])
def test_p2os_a_silent_or_garbling_robot_gets_a_stop_on_the_way_out(peer, p2os_moving, mode):
    base, commander = p2os_moving
    t0 = time.monotonic()
    peer.mode = mode
    t_stop = wait_for(lambda: p2os_first_zero_after(peer, t0, conn=1))
    assert_stopped_in_time(f"P2OS link loss ({mode})", t0, t_stop)
    assert wait_for(lambda: base.stats["link_downs"] == 1, 1.0)
    assert base.stats["watchdog_stops"] == 0, "the commander was starved: the watchdog stopped it"


def test_p2os_motors_off_is_stopped_at_once(peer, p2os_moving):
    base, commander = p2os_moving
    t0 = time.monotonic()
    peer.sip = replace(peer.sip, flags=0x02)            # motor switch off
    assert_stopped_in_time("P2OS drive fault", t0, wait_for(lambda: p2os_first_zero_after(peer, t0)))
    assert base.drive_fault["device"] == "P2OS motors"


def test_p2os_a_reconnect_starts_with_a_stop(peer, p2os_moving):
    base, commander = p2os_moving
    t0 = time.monotonic()
    peer.close()                                        # a pulled cable; the commander goes on
    def first_vel_after_open():
        second = [r for r in list(peer.received) if r.conn == 2]
        names = [r.name for r in second]
        if "OPEN" not in names:
            return None
        return next((r for r in second[names.index("OPEN"):] if r.name.startswith("VEL")), None)
    first_vel = wait_for(first_vel_after_open)
    assert first_vel is not None, "no velocity command after the reconnect's OPEN"
    names = [r.name for r in list(peer.received) if r.conn == 2]
    assert first_vel.name == "VEL 0", names
    print(f"P2OS reconnect: {(first_vel.t - t0) * 1000:.0f} ms after the hang-up, starting with VEL 0")


def test_p2os_stop_and_close_while_moving(peer, p2os_moving):
    base, commander = p2os_moving
    commander.halt()
    t0 = time.monotonic()
    base.stop()                         # (within 0.12 s: before the watchdog could stop it)
    assert_stopped_in_time("P2OS stop()", t0, wait_for(lambda: p2os_first_zero_after(peer, t0), 0.12))
    base.command(SPEED, 0.0)                               # moving again ...
    assert wait_for(lambda: any(r.name == "VEL 300" and r.t > t0 for r in p2os_vel(peer)))
    t1 = time.monotonic()
    base.close()                                           # ... and closed while moving
    assert_stopped_in_time("P2OS close()", t1, wait_for(lambda: p2os_first_zero_after(peer, t1)))
    assert peer.names()[-3:] == ["VEL 0", "RVEL 0", "CLOSE"]


# -- rFLEX: the emulated controller on a pty, each command stamped as it arrives ----------------

@pytest.fixture
def rflex_moving():
    from tests.robots.rflex_helpers import BoxWorld, StepSim
    from robots.clock import RealClock
    from robots.rflex import protocol as rp
    from robots.rflex.driver import RFlexBase
    from robots.rflex.emulator import RFlexEmulator

    class Stamping(RFlexEmulator):
        """Each decoded command with the monotonic time it arrived."""
        def receive(self, data: bytes) -> None:
            t = time.monotonic()
            before = len(self.controller.commands)
            super().receive(data)
            self.stamped.extend((t, c) for _, c in self.controller.commands[before:])

    world = BoxWorld()
    sim = StepSim(world)
    emulator = Stamping(world, clock=RealClock())
    emulator.stamped = []
    emulator.attach(sim)
    url = emulator.serve_pty()
    emulator.start_clock(sim)
    base = RFlexBase(load_profile("perses").limits, url)
    base.open()
    commander = Commander(base)

    def zero_after(t: float):
        return next((at for at, c in list(emulator.stamped)
                     if at >= t and isinstance(c, rp.SetDir) and c.axis == rp.TRANSLATION_AXIS
                     and c.velocity == 0), None)
    emulator.zero_after = zero_after
    assert wait_for(lambda: world.body.v > 0.1), "never moved"
    yield base, emulator, commander
    commander.halt()
    base.close()
    emulator.close()


def test_rflex_a_hung_tick_loop_is_stopped_by_the_watchdog(rflex_moving):
    base, emulator, commander = rflex_moving
    t0 = commander.halt()
    assert_stopped_in_time("rFLEX watchdog", t0, wait_for(lambda: emulator.zero_after(t0)))
    assert emulator.controller.failsafe_stops == 0             # the driver, not the failsafe


def test_rflex_a_silent_controller_is_sent_a_stop(rflex_moving):
    base, emulator, commander = rflex_moving
    t0 = time.monotonic()
    emulator.muted = True                                      # reports stop; commands arrive
    assert_stopped_in_time("rFLEX silent controller", t0, wait_for(lambda: emulator.zero_after(t0)))
    assert emulator.controller.failsafe_stops == 0


def test_rflex_brake_set_by_itself_is_stopped(rflex_moving):
    from robots.rflex import protocol as rp
    base, emulator, commander = rflex_moving
    with emulator._lock:
        emulator.controller.brake = True                       # the e-stop
    t0 = time.monotonic()
    status = rp.Simple(rp.SYS, rp.SYS_STATUS)
    seen = wait_for(lambda: next((at for at, c in list(emulator.stamped)
                                  if at >= t0 and c == status), None), timeout=3.0)
    assert seen is not None, "the driver never asked for the status"
    assert_stopped_in_time("rFLEX brake fault", seen, wait_for(lambda: emulator.zero_after(seen)))
    assert base.drive_fault["device"] == "rFLEX brake"


def test_rflex_stop_and_close_while_moving(rflex_moving):
    from robots.rflex import protocol as rp
    base, emulator, commander = rflex_moving
    commander.halt()
    base.command(SPEED, 0.0)
    t0 = time.monotonic()
    base.stop()                         # (within 0.12 s: before the watchdog could stop it)
    assert_stopped_in_time("rFLEX stop()", t0, wait_for(lambda: emulator.zero_after(t0), 0.12))
    base.command(SPEED, 0.0)
    time.sleep(0.05)
    t1 = time.monotonic()
    base.close()
    assert_stopped_in_time("rFLEX close()", t1, wait_for(lambda: emulator.zero_after(t1)))
    assert wait_for(lambda: any(at >= t1 and c == rp.Simple(rp.MOT, rp.MOT_BRAKE_SET)
                                for at, c in list(emulator.stamped)))


# -- CANopen: two emulated drives on a virtual bus; each drive logs its RPDOs with their times ---

@pytest.fixture
def canopen_moving():
    from robots.canopen.driver import CanOpenBase
    argos, clock, emulator = argos_drives_in_real_time()
    base = CanOpenBase(argos.limits, f"virtual:{emulator.channel}", clock=clock,
                       config=emulator.config)
    base.open()
    commander = Commander(base)
    assert wait_for(lambda: emulator.drives[1].target > 0), "never moved"
    yield base, emulator, commander
    commander.halt()
    base.close()
    emulator.close()


def can_zero_after(drive, t: float):
    return next((at for at, _, target in list(drive.rpdo_log) if at >= t and target == 0), None)


def test_canopen_a_hung_tick_loop_is_stopped_by_the_watchdog(canopen_moving):
    base, emulator, commander = canopen_moving
    t0 = commander.halt()
    for node in (1, 2):
        assert_stopped_in_time(f"CANopen watchdog, node {node}", t0,
                               wait_for(lambda: can_zero_after(emulator.drives[node], t0)))


@pytest.mark.parametrize("fault", ["EMCY 0x2310", "heartbeat loss", "bus-off"])
def test_canopen_a_fault_quick_stops_the_other_drive(canopen_moving, fault):
    base, emulator, commander = canopen_moving
    t0 = time.monotonic()
    if fault == "EMCY 0x2310":
        emulator.inject_fault(1, 0x2310)
    elif fault == "heartbeat loss":
        emulator.power_off(1)                   # (it waits for the emulator's lock) ...
        t0 = time.monotonic()                   # ... silent from here
    else:
        emulator.bus_error("bus-off")
    right = emulator.drives[2]
    t_stop = wait_for(lambda: next((at for at, word, target in list(right.rpdo_log)
                                    if at >= t0 and target == 0 and word == 0x0002), None))
    assert_stopped_in_time(f"CANopen {fault}", t0, t_stop)
    assert base.fault is not None


def test_canopen_stop_while_moving(canopen_moving):
    base, emulator, commander = canopen_moving
    commander.halt()
    base.command(SPEED, 0.0)
    t0 = time.monotonic()
    base.stop()
    for node in (1, 2):
        assert_stopped_in_time(f"CANopen stop(), node {node}", t0,
                               wait_for(lambda: can_zero_after(emulator.drives[node], t0), 0.12))


def test_canopen_close_while_moving_quick_stops_both(canopen_moving):
    base, emulator, commander = canopen_moving
    commander.halt()
    base.command(SPEED, 0.0)
    t0 = time.monotonic()
    base.close()
    for node in (1, 2):
        assert_stopped_in_time(f"CANopen close(), node {node}", t0,
                               can_zero_after(emulator.drives[node], t0))
