"""Frames sent without python-can's deepcopy (robots/canopen/virtual_send.py) arrive as
`VirtualBus.send` delivers them: the same fields, a copy of their own, on every other bus of
the channel (and on the sender's own when it asks for them), and a patched `send` is used."""
from __future__ import annotations

import itertools

import can
from can.interfaces.virtual import VirtualBus

from robots.canopen.virtual_send import send_copies, virtual_sender

FIELDS = ("timestamp", "arbitration_id", "is_extended_id", "is_remote_frame", "is_error_frame",
          "channel", "dlc", "data", "is_fd", "is_rx", "bitrate_switch", "error_state_indicator")
_channels = itertools.count()


def received(send, receive_own: bool, msg: can.Message, channel: str) -> list[dict]:
    """What each bus of a channel of three receives when the first sends `msg` with
    `send(bus, msg)`."""
    buses = [VirtualBus(channel=channel, preserve_timestamps=True,
                        receive_own_messages=receive_own and k == 0) for k in range(3)]
    try:
        send(buses[0], msg)
        got = [bus.recv(0) for bus in buses]
    finally:
        for bus in buses:
            bus.shutdown()
    assert got[0] is not msg and got[1] is not msg and got[1] is not got[2]
    return [None if m is None else {f: getattr(m, f) for f in FIELDS} for m in got]


def test_the_copies_are_what_virtualbus_send_delivers():
    frames = [can.Message(timestamp=12.5, arbitration_id=0x601, data=[0x40, 0x41, 0x60, 0, 0, 0, 0, 0],
                          is_extended_id=False),
              can.Message(timestamp=3.0, arbitration_id=0x1ABCDE, data=b"\x01\x02",
                          is_extended_id=True),
              can.Message(timestamp=1.0, arbitration_id=0x80, is_remote_frame=True, dlc=0)]
    for msg, own in itertools.product(frames, (False, True)):
        channel = f"virtual-send-{next(_channels)}"          # the same name for both
        ours = received(lambda bus, m: send_copies(bus, m, None), own, msg, channel)
        theirs = received(lambda bus, m: VirtualBus.send(bus, m, None), own, msg, channel)
        assert ours == theirs
        assert (ours[0] is not None) == own and ours[1] is not None


def test_a_send_set_on_the_bus_itself_is_used():
    bus = VirtualBus(channel=f"virtual-send-{next(_channels)}")
    try:
        seen = []
        sender = virtual_sender(bus)
        bus.send = lambda msg, timeout=None: seen.append(msg)       # as a test's fault does
        msg = can.Message(arbitration_id=1, data=b"\x00")
        sender(msg, None)
        assert seen == [msg]
    finally:
        bus.shutdown()
