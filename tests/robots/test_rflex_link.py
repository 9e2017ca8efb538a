"""RFlexBase over a real pty (and TCP) in real time: watchdog, unplug and reconnect."""
from __future__ import annotations

import time

import pytest

from rflex_helpers import PERSES, BoxWorld, StepSim, wait_until
from robots.clock import RealClock
from robots.exceptions import LinkError
from robots.link import PtyPair
from robots.rflex import protocol as p
from robots.rflex.driver import RFlexBase
from robots.rflex.emulator import RFlexEmulator


def real_time_emulator(world=None, link=None):
    """A controller on a pty whose own thread steps a small world in real time."""
    world = world or BoxWorld()
    clock = RealClock()
    sim = StepSim(world)
    emulator = RFlexEmulator(world, clock=clock)
    emulator.attach(sim)
    path = emulator.serve_pty(link=link)
    emulator.start_clock(sim)
    return emulator, path


def set_dirs(emulator):
    return [c for _, c in list(emulator.controller.commands) if isinstance(c, p.SetDir)]


def test_watchdog_sends_zero_over_a_pty_without_anyone_calling():
    emulator, path = real_time_emulator()
    base = RFlexBase(PERSES.limits, path)
    try:
        base.open()
        base.command(0.3, 0.0)
        sent_at = time.monotonic()
        assert wait_until(lambda: any(c.axis == 0 and c.velocity > 0 for c in set_dirs(emulator)))
        seen = len(set_dirs(emulator))
        assert wait_until(lambda: any(c.axis == 0 and c.velocity == 0
                                      for c in set_dirs(emulator)[seen:]), timeout=3.0)
        delay = time.monotonic() - sent_at
        print(f"zero seen by the controller {delay * 1000:.0f} ms after the last command")
        assert base.read_state().extra["watchdog_expirations"] == 1
        assert delay < 1.0            # 150 ms by design; slack for a loaded machine
        assert emulator.controller.failsafe_stops == 0        # the driver, not the failsafe
        assert wait_until(lambda: emulator.world.body.v == 0.0)
    finally:
        base.close()
        emulator.close()


def test_open_times_out_on_a_silent_line():
    with PtyPair() as pty:
        base = RFlexBase(PERSES.limits, pty.path, open_timeout=0.3)
        with pytest.raises(LinkError, match="no motor reports"):
            base.open()


def test_unplug_and_reconnect_without_resuming_motion(tmp_path):
    link = tmp_path / "b21r"
    world = BoxWorld()
    emulator, path = real_time_emulator(world, link=str(link))
    base = RFlexBase(PERSES.limits, path)
    replacement = None
    try:
        base.open()
        for _ in range(5):
            base.command(0.3, 0.0)
            time.sleep(0.05)
        assert wait_until(lambda: world.body.v > 0.05)
        emulator.unplug()
        assert wait_until(lambda: not base.read_state().link_up)
        base.command(0.3, 0.0)                         # ignored while the link is down
        assert wait_until(lambda: world.body.v == 0.0)  # the controller's failsafe stopped it
        emulator.close()

        replacement, _ = real_time_emulator(world, link=str(link))
        assert wait_until(lambda: base.read_state().link_up, timeout=10.0)
        assert base.read_state().extra["reconnects"] >= 1
        time.sleep(0.3)
        # the driver's watchdog writes a zero at its own pace; on a loaded machine the first
        # may come later than 0.3 s after the reconnection (seen in a parallel suite run)
        assert wait_until(lambda: set_dirs(replacement), timeout=5.0)
        after = set_dirs(replacement)
        assert after and all(c.velocity == 0 for c in after)   # nothing resumed by itself
        assert world.body.v == 0.0 and replacement.controller.brake is False
        base.command(0.2, 0.0)                                   # a fresh command drives again
        assert wait_until(lambda: world.body.v > 0.05)
    finally:
        base.close()
        emulator.close()
        if replacement is not None:
            replacement.close()


def test_over_tcp():
    world = BoxWorld()
    clock = RealClock()
    sim = StepSim(world)
    emulator = RFlexEmulator(world, clock=clock)
    emulator.attach(sim)
    host, port = emulator.serve_tcp("127.0.0.1", 0)
    emulator.start_clock(sim)
    base = RFlexBase(PERSES.limits, f"socket://{host}:{port}")
    try:
        base.open()
        # commanded again while waiting, as a control loop does: one command lasts only the
        # driver's 0.15 s watchdog, which a loaded machine can spend before the body moves
        assert wait_until(lambda: base.command(0.2, 0.1) or world.body.v > 0.05)
        assert base.read_state().link_up
    finally:
        base.close()
        emulator.close()


def test_interbot_emulate_rflex_serves_a_driver(capsys):
    import argparse
    import re
    import threading

    from robots.emulate import EmulateCommand

    command = EmulateCommand()
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    args = parser.parse_args(["rflex", "--tcp", "0"])
    stop = threading.Event()
    runner = threading.Thread(target=command.run, args=(args, stop), daemon=True)
    runner.start()
    try:
        address = None

        def ready():
            nonlocal address
            found = re.search(r"socket://[\d.]+:\d+", capsys.readouterr().out)
            address = address or (found.group(0) if found else None)
            return address is not None
        assert wait_until(ready)
        base = RFlexBase(PERSES.limits, address, **PERSES.base.options)
        try:
            base.open()
            for _ in range(5):
                base.command(0.2, 0.0)
                time.sleep(0.05)
            assert wait_until(lambda: base.read_state().v > 0.05)
            assert sum(r < 5.0 for r in base.read_state().sonar) > 0    # the office walls
        finally:
            base.close()
    finally:
        stop.set()
        runner.join(timeout=5)
    assert not runner.is_alive()


def test_a_second_tcp_client_inherits_no_velocity_and_no_released_brake():
    """Take-over on TCP: the newest client has the line; the first one's 0.4 m/s and released
    brake end at once, not when the controller's failsafe runs out."""
    import socket
    world = BoxWorld()
    clock = RealClock()
    sim = StepSim(world)
    emulator = RFlexEmulator(world, clock=clock)
    emulator.attach(sim)
    host, port = emulator.serve_tcp("127.0.0.1", 0)
    emulator.start_clock(sim)
    base = RFlexBase(PERSES.limits, f"socket://{host}:{port}")
    second = None
    try:
        base.open()
        assert wait_until(lambda: base.command(0.4, 0.0) or world.body.v > 0.2, every=0.03)
        assert emulator.controller.brake is False
        base.watchdog.stop()                      # the first client freezes (no stop, no
        base._running = False                     # resend, no reconnect) ...
        base._thread.join(timeout=1.0)
        second = socket.create_connection((host, port))      # ... and another takes over
        taken_at = time.monotonic()
        assert wait_until(lambda: emulator.connections == 2, timeout=2.0)
        assert wait_until(lambda: world.body.cmd_v == 0.0, timeout=0.2)
        assert emulator.controller.brake is True
        assert emulator.controller.failsafe_stops == 0          # not the failsafe
        print(f"stopped {(time.monotonic() - taken_at) * 1000:.0f} ms after the take-over")
    finally:
        if second is not None:
            second.close()
        base.close()
        emulator.close()
