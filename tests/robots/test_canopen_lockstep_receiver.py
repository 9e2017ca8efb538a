"""`LockStepReceiver`: the host side of the CAN lock-step, read on the caller's thread.

What it must keep of python-can's Notifier: every frame to every listener, in order; a
listener's exception to the listeners' `on_error`. What it adds: no thread, and no wait on
another reader (a listener that sends, or a second thread, leaves its frames to the reader).
"""
from __future__ import annotations

import itertools
import threading
import time

import can
import pytest

from robots.canopen.bus import DriverBus, LockStepReceiver
from robots.link.lockstep import ByteCounter

_channels = itertools.count(1)


class Recorder(can.Listener):
    def __init__(self, react=None) -> None:
        self.seen: list[tuple[int, str]] = []
        self.react = react or {}

    def on_message_received(self, msg: can.Message) -> None:
        self.seen.append((msg.arbitration_id, threading.current_thread().name))
        action = self.react.get(msg.arbitration_id)
        if action is not None:
            action()


@pytest.fixture
def pair():
    """A host bus (wrapped, as the driver's) and a peer on the same virtual channel."""
    channel = f"receiver-test-{next(_channels)}"
    host = can.Bus(interface="virtual", channel=channel)
    peer = can.Bus(interface="virtual", channel=channel)
    yield DriverBus(host), peer
    host.shutdown()
    peer.shutdown()


def frame(can_id: int) -> can.Message:
    return can.Message(arbitration_id=can_id, data=b"\x01", is_extended_id=False)


def test_every_waiting_frame_goes_to_every_listener_in_order_on_the_callers_thread(pair):
    bus, peer = pair
    first, second = Recorder(), Recorder()
    receiver = LockStepReceiver(bus, [first, second])
    for can_id in (0x181, 0x281, 0x701):
        peer.send(frame(can_id))
    receiver.receive()
    me = threading.current_thread().name
    assert first.seen == second.seen == [(0x181, me), (0x281, me), (0x701, me)]
    receiver.receive()                               # nothing waiting: returns, handles nothing
    assert len(first.seen) == len(second.seen) == 3


def test_a_listener_that_sends_has_the_answer_handled_after_the_frames_before_it(pair):
    """As in the driver: its send reads the bus again while the reader is in a listener."""
    bus, peer = pair
    receiver = LockStepReceiver(bus, [])

    def answer() -> None:                            # a send whose answer is at once on the bus
        peer.send(frame(0x581))
        receiver.receive()                           # the nested read leaves it to the reader
    recorder = Recorder({0x181: answer})
    receiver.listeners.append(recorder)
    peer.send(frame(0x181))
    peer.send(frame(0x281))
    receiver.receive()
    assert [can_id for can_id, _ in recorder.seen] == [0x181, 0x281, 0x581]


def test_a_second_thread_never_waits_for_the_reader_and_its_frames_are_handled(pair):
    bus, peer = pair
    inside, release = threading.Event(), threading.Event()

    def hold() -> None:                              # the reader is busy in a listener
        inside.set()
        assert release.wait(5.0)
    recorder = Recorder({0x181: hold})
    receiver = LockStepReceiver(bus, [recorder])
    peer.send(frame(0x181))
    reader = threading.Thread(target=receiver.receive, name="reader")
    reader.start()
    assert inside.wait(5.0)
    peer.send(frame(0x182))
    receiver.receive()                               # returns at once: the reader has it
    assert [can_id for can_id, _ in recorder.seen] == [0x181]
    release.set()
    reader.join(5.0)
    assert recorder.seen == [(0x181, "reader"), (0x182, "reader")]


def test_a_listeners_exception_goes_to_on_error_as_with_the_notifier(pair):
    bus, peer = pair

    class Failing(can.Listener):
        def on_message_received(self, msg):
            raise ValueError(f"cannot decode {msg.arbitration_id:03X}")

    class Errors(can.Listener):
        def __init__(self):
            self.errors = []

        def on_message_received(self, msg):
            pass

        def on_error(self, exc):
            self.errors.append(str(exc))
    errors = Errors()
    receiver = LockStepReceiver(bus, [Failing(), errors])
    peer.send(frame(0x181))
    peer.send(frame(0x182))
    receiver.receive()                               # handled: reading goes on
    assert errors.errors == ["cannot decode 181", "cannot decode 182"]
    alone = LockStepReceiver(bus, [Failing()])       # nobody handles it: raised, as the Notifier
    peer.send(frame(0x183))
    with pytest.raises(ValueError, match="183"):
        alone.receive()


def test_drain_waits_for_the_frames_counted_as_sent(pair):
    bus, peer = pair
    counter = ByteCounter()

    class Counting(can.Listener):
        def on_message_received(self, msg):
            counter.got(1)
    receiver = LockStepReceiver(bus, [Counting()], counter)
    counter.wrote(2)
    peer.send(frame(0x181))
    peer.send(frame(0x182))
    assert receiver.drain(1.0) and counter.backlog() == 0
    counter.wrote(1)                                 # counted as sent, never on the bus
    assert not receiver.drain(0.05)
    bus.lost = can.CanOperationError("adapter gone")  # a bus found lost brings nothing more
    t0 = time.monotonic()
    assert not receiver.drain(5.0) and time.monotonic() - t0 < 1.0
