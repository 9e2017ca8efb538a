"""The VISCA head driver against its emulator, over a raw pty and over TCP 127.0.0.1: pointing,
the profile's limits, and each fault (silence, garbage, error replies, a pulled cable)."""
from __future__ import annotations

import math
import time
from dataclasses import replace

import pytest

from robots.exceptions import HandshakeError
from robots.link.pty import PtyPair
from robots.profile import load_profile
from robots.visca import protocol as p
from robots.visca.driver import ViscaHead
from robots.visca.emulator import Camera, ViscaEmulator

HOROS = load_profile("horos")


def serve(emulator: ViscaEmulator, where: str) -> str:
    emulator.start_clock()
    if where == "pty":
        return emulator.serve_pty()
    host, port = emulator.serve_tcp("127.0.0.1", 0)
    return f"socket://{host}:{port}"


@pytest.fixture
def rig(request):
    """(emulator, head) for HOROS's [head] (or a changed spec), over a pty or TCP."""
    made = []

    def make(where: str = "pty", spec=None, emulator=None):
        spec = spec or HOROS.head
        emulator = emulator or ViscaEmulator.for_profile(replace(HOROS, head=spec))
        head = ViscaHead(spec, serve(emulator, where))
        made.append((emulator, head))
        head.open()
        return emulator, head
    yield make
    for emulator, head in made:
        head.close()
        emulator.close()


def degrees(pair) -> tuple[float, float]:
    return math.degrees(pair[0]), math.degrees(pair[1])


def wait_until(condition, timeout: float = 3.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.02)
    return condition()


@pytest.mark.parametrize("where", ["pty", "tcp"])
def test_points_the_head_and_reads_it_back(rig, where):
    emulator, head = rig(where)
    assert head.fault() is None and head.model is p.EVI_D31
    head.point(math.radians(60), math.radians(-10))
    assert wait_until(lambda: abs(degrees(head.read())[0] - 60) < 0.2
                      and abs(degrees(head.read())[1] + 10) < 0.2)
    assert degrees(emulator.camera.radians()) == pytest.approx((60, -10), abs=0.2)
    sent = [pkt for pkt in emulator.received if pkt[1:4] == b"\x01\x06\x02"]
    assert sent and all(pkt[4] == 0x18 and pkt[5] == 0x14 for pkt in sent)  # 80 deg/s rated


def test_moves_at_the_rated_speed(rig):
    emulator, head = rig()
    head.point(math.radians(100), 0.0)
    wait_until(lambda: degrees(head.read())[0] > 10)
    t0, pan0 = time.monotonic(), degrees(head.read())[0]
    time.sleep(0.5)
    rate = (degrees(head.read())[0] - pan0) / (time.monotonic() - t0)
    assert 55 < rate < 95                     # 80 deg/s, measured through 50 ms inquiries


def test_the_head_stops_at_the_profiles_limits(rig):
    spec = replace(HOROS.head, pan_max=math.radians(50), tilt_min=math.radians(-10))
    emulator, head = rig(spec=spec)
    head.point(math.radians(500), math.radians(-90))
    assert wait_until(lambda: degrees(head.read()) == pytest.approx((50, -10), abs=0.2))
    time.sleep(0.3)
    assert degrees(head.read()) == pytest.approx((50, -10), abs=0.2)
    for pkt in emulator.received:
        if pkt[1:4] == b"\x01\x06\x02":
            assert p.from_nibbles(pkt[6:10]) <= round(50 * 8.8)
            assert p.from_nibbles(pkt[10:14]) >= -10 * 12


def test_not_a_number_keeps_the_goal(rig):
    emulator, head = rig()
    head.point(math.radians(30), 0.0)
    head.point(float("nan"), float("inf"))
    assert wait_until(lambda: abs(degrees(head.read())[0] - 30) < 0.2)


def test_stop_cancels_the_motion_where_the_head_is(rig):
    slow = replace(HOROS.head, max_pan_rate=math.radians(10))
    emulator, head = rig(spec=slow)
    head.point(math.radians(100), 0.0)
    wait_until(lambda: degrees(head.read())[0] > 3)
    head.stop()
    assert wait_until(lambda: emulator.camera.motion is None)
    here = degrees(head.read())[0]
    time.sleep(0.4)
    assert degrees(head.read())[0] == pytest.approx(here, abs=0.2) and here < 20
    assert head.stats["cancels"] >= 1


def test_a_silent_head_is_a_fault_that_stops_it_and_nothing_resumes(rig):
    slow = replace(HOROS.head, max_pan_rate=math.radians(10))
    emulator, head = rig(spec=slow)
    head.point(math.radians(100), 0.0)
    wait_until(lambda: degrees(head.read())[0] > 3)
    emulator.muted = True
    assert wait_until(lambda: head.fault() is not None, 2.0)
    assert "no valid reply" in head.fault() and not head.link_up
    assert wait_until(lambda: emulator.camera.motion is None, 1.0)   # Cancel/Stop got through
    stopped = emulator.camera.pan
    emulator.muted = False
    assert wait_until(lambda: head.link_up, 4.0)
    assert head.fault() is None
    assert head.stats["link_downs"] == 1 and head.stats["reconnects"] == 1
    time.sleep(0.4)
    assert emulator.camera.pan == pytest.approx(stopped)       # the old goal is forgotten
    head.point(math.radians(30), 0.0)                          # a new command moves it again
    assert wait_until(lambda: abs(degrees(head.read())[0] - 30) < 0.2, 4.0)


class GarblingEmulator(ViscaEmulator):
    """Answers with bytes that form no VISCA packet once `garble` is set."""
    garble = False

    def _send(self, data: bytes) -> None:
        super()._send(bytes(b & 0x7F for b in data) if self.garble else data)


def test_a_head_sending_garbage_is_a_fault_that_says_so(rig):
    emulator = GarblingEmulator.for_profile(HOROS)
    emulator, head = rig(emulator=emulator)
    emulator.garble = True
    assert wait_until(lambda: head.fault() is not None, 2.0)
    assert "formed no packet" in head.fault()
    assert head.parser.stats.dropped_bytes > 0


class RefusingCamera(Camera):
    """Once `motions` / `inquiries` name an error, answers every motion / inquiry with it."""
    motions: p.ErrorCode | None = None
    inquiries: p.ErrorCode | None = None

    def receive(self, packet: bytes) -> bytes:
        if self.motions is not None and packet[1:3] == b"\x01\x06":
            socket = 0 if self.motions in (p.ErrorCode.SYNTAX, p.ErrorCode.BUFFER_FULL) else 1
            return p.error(self.address, socket, self.motions)
        if self.inquiries is not None and packet[1] == 0x09:
            return p.error(self.address, 0, self.inquiries)
        return super().receive(packet)


@pytest.mark.parametrize("code, name", [(p.ErrorCode.NOT_EXECUTABLE, "command not executable"),
                                        (p.ErrorCode.BUFFER_FULL, "command buffer full"),
                                        (p.ErrorCode.SYNTAX, "syntax error")])
def test_refused_motions_are_a_fault_naming_the_error(rig, code, name):
    camera = RefusingCamera(rated_pan_deg_s=80.0)
    emulator, head = rig(emulator=ViscaEmulator(camera))
    camera.motions = code                   # inquiries are still answered
    head.point(math.radians(40), 0.0)
    assert wait_until(lambda: head.fault() is not None, 2.0)
    assert f"3 error replies in a row, the last to AbsolutePosition: {name}" in head.fault()
    assert head.stats["errors"] >= 3
    assert emulator.camera.pan == 0.0
    busy = code in (p.ErrorCode.NOT_EXECUTABLE, p.ErrorCode.BUFFER_FULL)
    assert (head.stats["clears"] >= 3) == busy        # a busy camera is cleared (IF_Clear)
    assert (bytes.fromhex("81 01 00 01 FF") in emulator.received) == busy


def test_refused_inquiries_are_a_fault(rig):
    camera = RefusingCamera(rated_pan_deg_s=80.0)
    emulator, head = rig(emulator=ViscaEmulator(camera))
    camera.inquiries = p.ErrorCode.SYNTAX
    assert wait_until(lambda: head.fault() is not None, 2.0)
    assert "the last to Pan-tiltPosInq: syntax error" in head.fault()


def test_a_pulled_cable_is_a_fault(rig):
    emulator, head = rig("pty")
    emulator.unplug()
    assert wait_until(lambda: head.fault() is not None, 2.0)
    assert not head.link_up


def test_nothing_on_the_line_is_a_clear_handshake_error():
    with PtyPair() as pty:
        head = ViscaHead(HOROS.head, pty.path, reply_timeout=0.1)
        with pytest.raises(HandshakeError, match="no answer to AddressSet"):
            head.open()
        head.close()


def test_the_cameras_own_model_wins(rig):
    d70 = ViscaEmulator(Camera(p.EVI_D70, rated_pan_deg_s=80.0))
    emulator, head = rig(emulator=d70)
    assert head.model is p.EVI_D70
    head.point(math.radians(-45), math.radians(20))
    assert wait_until(lambda: degrees(head.read()) == pytest.approx((-45, 20), abs=0.2))
