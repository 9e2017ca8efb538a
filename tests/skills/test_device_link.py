"""A device's faults become link episodes: one `link` down with the reason, one up with how long
it lasted, however many ticks the episode spans; a device without `fault()` never faults."""
from __future__ import annotations

import pytest

from skills.device_link import DeviceLink
from skills.events import EventLog


class Device:
    def __init__(self) -> None:
        self.why: str | None = None

    def fault(self) -> str | None:
        return self.why


def test_one_episode_is_two_events():
    events, device = EventLog(), Device()
    link = DeviceLink(events, "camera")
    t = 0.0
    for why in [None] * 3 + ["camera '0': no frame for 1.2 s"] * 10 + [None] * 3:
        device.why = why
        assert link.update(device, t) == why
        t += 0.1
    got = [e.as_dict() for e in events.drain()]
    assert [(e["kind"], e["device"], e["state"]) for e in got] == [
        ("link", "camera", "down"), ("link", "camera", "up")]
    assert got[0]["reason"] == "camera '0': no frame for 1.2 s"
    assert got[1]["after"] == pytest.approx(1.0)


def test_a_device_without_fault_never_faults():
    events = EventLog()
    assert DeviceLink(events, "head").update(object(), 1.0) is None
    assert events.drain() == []
