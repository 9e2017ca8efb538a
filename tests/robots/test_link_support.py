"""The shared link helpers: watchdog, back-off, raw pty pair, lock-step counters."""
from __future__ import annotations

import os
import termios
import threading

import pytest
import serial

from robots.exceptions import LinkError
from robots.link import Backoff, ByteCounter, CommandWatchdog, PtyPair
from robots.link.port import open_serial


def test_watchdog_check_fires_once_per_silence():
    fired = []
    dog = CommandWatchdog(0.2, lambda: fired.append(1))
    assert not dog.check(10.0)              # never fed: nothing to guard
    dog.feed(now=1.0)
    assert not dog.check(1.1)
    assert dog.check(1.2)
    assert not dog.check(5.0)               # fires once; only a feed re-arms it
    dog.feed(now=5.0)
    assert dog.check(5.3)
    assert fired == [1, 1]


def test_watchdog_thread_fires_without_anyone_calling_it():
    fired = threading.Event()
    dog = CommandWatchdog(0.05, fired.set)
    dog.start()
    try:
        dog.feed()
        assert fired.wait(2.0)
        assert dog.expirations == 1 and not dog.armed
        fired.clear()
        dog.disarm()
        assert not fired.wait(0.15)
    finally:
        dog.stop()


def test_backoff_grows_to_its_ceiling_and_resets():
    policy = Backoff(initial=0.1, factor=2, maximum=0.5)
    assert [policy.next_delay() for _ in range(5)] == pytest.approx([0.1, 0.2, 0.4, 0.5, 0.5])
    policy.reset()
    assert policy.next_delay() == pytest.approx(0.1)


def test_backoff_jitter_is_seeded_and_bounded():
    a = [Backoff(jitter=0.5, seed=3).next_delay() for _ in range(3)]
    b = [Backoff(jitter=0.5, seed=3).next_delay() for _ in range(3)]
    assert a == b and all(0.1 <= d <= 0.15 for d in a)


def test_pty_is_raw_both_ways():
    with PtyPair() as pty:
        port = serial.Serial(pty.path, 9600, timeout=1)
        everything = bytes(range(256))
        port.write(everything)
        got = b""
        while len(got) < 256:
            chunk = pty.read(timeout=1)
            assert chunk
            got += chunk
        assert got == everything
        pty.write(everything)
        assert port.read(256) == everything
        port.close()


def test_pty_tells_the_baud_the_driver_set():
    with PtyPair() as pty:
        port = serial.Serial(pty.path, 38400)
        assert pty.line_speed() == termios.B38400
        port.close()


def test_pty_link_survives_a_replug(tmp_path):
    link = tmp_path / "ttyROBOT"
    first = PtyPair(link=link)
    old = os.path.realpath(link)
    first.close()
    second = PtyPair(link=link)
    try:
        assert os.path.realpath(link) != old or second.slave_name == old
        port = serial.Serial(str(link), 9600, timeout=1)
        second.write(b"\x0A\x03")
        assert port.read(2) == b"\x0A\x03"
        port.close()
    finally:
        second.close()


def test_an_unplugged_ptys_link_goes_with_it_and_never_leads_into_another_line(tmp_path):
    # the kernel gives a closed pty's number to the next one made (here or in another
    # process): a link left behind led a reconnecting driver into a stranger's line
    link = tmp_path / "ttyROBOT"
    first = PtyPair(link=link)
    first.close()
    assert not os.path.lexists(link)
    stranger = PtyPair()
    try:
        with pytest.raises(LinkError, match="cannot open"):
            open_serial(str(link), "the port", baudrate=9600)
    finally:
        stranger.close()


def test_an_old_ptys_close_leaves_a_replacements_link_alone(tmp_path):
    link = tmp_path / "ttyROBOT"
    old = PtyPair(link=link)
    new = PtyPair(link=link)
    try:
        old.close()
        assert os.path.realpath(link) == os.path.realpath(new.slave_name)
    finally:
        new.close()
    assert not os.path.lexists(link)


def test_a_second_driver_is_refused_a_line_already_in_use():
    with PtyPair() as pty:
        first = open_serial(pty.path, "the port", baudrate=9600, timeout=0)
        try:
            with pytest.raises(LinkError, match="another program has it open"):
                open_serial(pty.path, "the port", baudrate=9600, timeout=0)
        finally:
            first.close()
        again = open_serial(pty.path, "the port", baudrate=9600, timeout=0)   # free once closed
        again.close()


def test_byte_counter_waits_until_drained():
    counter = ByteCounter()
    counter.wrote(10)
    assert not counter.wait_drained(0.01)
    threading.Timer(0.02, counter.got, args=(10,)).start()
    assert counter.wait_drained(2.0)
    assert counter.backlog() == 0


def test_lockstep_deliver_runs_the_emulators_pump_on_the_callers_thread():
    from robots.link.lockstep import LockStep
    step = LockStep()
    threads = []

    def pump(timeout: float) -> None:          # the emulator reads one byte per call
        threads.append(threading.current_thread())
        step.to_device.got(1)
    step.pump = pump
    step.to_device.wrote(3)
    assert step.deliver(1.0)
    assert threads == [threading.current_thread()] * 3


def test_lockstep_deliver_falls_back_to_waiting_when_the_line_is_dropped():
    from robots.link.lockstep import LockStep
    step = LockStep()

    def pump(timeout: float) -> None:          # hung up: the host takes its pump away
        step.pump = None
    step.pump = pump
    step.to_device.wrote(2)
    threading.Timer(0.05, lambda: step.to_device.got(2)).start()   # a reader thread, late
    assert step.deliver(2.0)
    step.to_device.wrote(1)
    assert not step.deliver(0.05)              # nobody reads: times out, does not hang


def test_an_in_process_emulator_on_a_simulated_clock_reads_on_no_thread_of_its_own():
    from robots.hardware import open_hardware
    hardware = open_hardware("horos", fast=True)
    try:
        for _ in range(5):
            hardware.base.command(0.1, 0.0)
            hardware.sense()
            hardware.clock.advance(0.1)
        names = [t.name for t in threading.enumerate()]
        assert not any("reader" in name for name in names), names
        assert hardware.base.read_state().v > 0.0          # the commands got through
    finally:
        hardware.close()



def test_stamped_arrival_learns_the_stamp_clock_offset_and_ages_a_backlog():
    from robots.link.arrival import StampedArrival
    arrival = StampedArrival(drift=0.01)
    skew = 1000.0                                   # the stamping clock is another machine's
    assert arrival.arrived(5.0 - skew, wall_now=5.0, now=50.0) == 50.0     # handled at once
    # a frame stamped 0.8 s before it is handled (it waited behind a flood) arrived 0.8 s ago
    assert arrival.arrived(5.2 - skew, wall_now=6.0, now=51.0) == pytest.approx(50.2, abs=0.02)
    assert arrival.arrived(None, wall_now=6.0, now=51.0) == 51.0          # no stamp: now
    # a clock step backwards is forgotten as the offset creeps up by drift s per s
    late = [arrival.arrived(10.0 + k - skew - 0.5, wall_now=10.0 + k, now=55.0 + k)
            for k in range(0, 100, 10)]
    assert late[0] == pytest.approx(55.0 - 0.5, abs=0.06)
    assert late[-1] == pytest.approx(145.0, abs=0.01)
