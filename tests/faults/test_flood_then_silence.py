"""A robot end that floods its link and then falls silent is noticed as silent within 0.5 s.

The drivers read everything that has arrived in one call and decode only the newest of a flood
(robots.link.arrival), and the age of the newest good packet decides whether the link is alive.
Before that, on TCP a driver read one byte per call: after 5000 queued SIPs silence was noticed
after 4.2 s, and after a second of flooding not within a minute."""
from __future__ import annotations

import time

import pytest

from robots.p2os.driver import P2OSBase
from robots.profile import load_profile
from tests.faults.conftest import argos_drives_in_real_time

NOTICED_WITHIN = 0.5          # s from the robot end's last byte to "link down" (issue 24)


def wait_until(predicate, timeout: float) -> float | None:
    """The monotonic time `predicate` first held (polled every 5 ms), or None."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return time.monotonic()
        time.sleep(0.005)
    return None


@pytest.fixture
def p2os_on_peer(peer):
    base = P2OSBase(load_profile("horos").limits, peer.url, reconnect=False)
    base.open()
    yield base
    base.close()


@pytest.mark.parametrize("how", ["5000 queued SIPs", "1 s of flooding"])
def test_p2os_over_tcp_notices_silence_after_a_flood(peer, p2os_on_peer, how):
    base = p2os_on_peer
    assert wait_until(lambda: base.stats["sips"] >= 3, 2.0)
    if how == "5000 queued SIPs":
        silent_from = peer.burst(5000)
    else:
        silent_from = peer.flood_then_silence(1.0)
    down_at = wait_until(lambda: base.stats["link_downs"] > 0, 10.0)
    assert down_at is not None, f"silence after {how} was never noticed"
    print(f"{how}: link down {(down_at - silent_from) * 1000:.0f} ms after the last byte")
    assert down_at - silent_from <= NOTICED_WITHIN
    assert "no SIP" in base.last_error
    assert base.parser.stats.packets > 100       # the flood was read, not refused


# -- rFLEX: the emulated controller on a pty (a serial line) and on TCP -------------------------

def rflex_controller(transport: str):
    """An rFLEX emulator stepping a small world in real time; (emulator, url)."""
    from tests.robots.rflex_helpers import BoxWorld, StepSim
    from robots.clock import RealClock
    from robots.rflex.emulator import RFlexEmulator
    world = BoxWorld()
    sim = StepSim(world)
    emulator = RFlexEmulator(world, clock=RealClock())
    emulator.attach(sim)
    if transport == "tcp":
        host, port = emulator.serve_tcp("127.0.0.1", 0)
        url = f"socket://{host}:{port}"
    else:
        url = emulator.serve_pty()
    emulator.start_clock(sim)
    return emulator, url


def rflex_flood(emulator, how: str) -> float:
    """Mute the controller's own reports, flood motor reports, fall silent; returns when the
    last flooded byte was written."""
    reports = emulator.controller._motor_reports()          # both axes, one report each
    emulator.muted = True
    transport = emulator._transport
    if how == "5000 queued reports":
        transport.write(reports * 2500)
    else:
        until = time.monotonic() + 1.0
        while time.monotonic() < until:
            transport.write(reports * 20)
    return time.monotonic()


@pytest.mark.parametrize("transport", ["pty", "tcp"])
@pytest.mark.parametrize("how", ["5000 queued reports", "1 s of flooding"])
def test_rflex_notices_silence_after_a_flood(transport, how):
    from robots.rflex.driver import RFlexBase
    emulator, url = rflex_controller(transport)
    base = RFlexBase(load_profile("perses").limits, url)
    try:
        base.open()
        assert base.read_state().link_up
        silent_from = rflex_flood(emulator, how)
        down_at = wait_until(lambda: not base.read_state().link_up, 10.0)
        assert down_at is not None, f"silence after {how} was never noticed"
        print(f"{transport}, {how}: link down {(down_at - silent_from) * 1000:.0f} ms after "
              f"the last byte; {base.report_count} reports decoded")
        assert down_at - silent_from <= NOTICED_WITHIN
        assert base.report_count > 100               # the flood was read, not refused
    finally:
        base.close()
        emulator.close()


# -- a streaming sensor (robots/link/sensor.py): a Hokuyo UST-10LX on TCP ------------------------

def test_a_laser_over_tcp_notices_silence_after_a_flood():
    from tests.robots.test_hokuyo_driver import ARGOS, start
    from robots.hokuyo.driver import HokuyoLaser
    from robots.hokuyo.emulator import HokuyoEmulator

    class Recording(HokuyoEmulator):
        last_scan = b""

        def _send(self, data: bytes) -> None:
            if b"\n99b\n" in data:
                self.last_scan = data
            super()._send(data)

    emulator, url, _, clock = start(ARGOS, Recording, tcp=True)
    laser = HokuyoLaser.for_profile(ARGOS, url, clock=clock, reply_timeout=0.3)
    try:
        laser.open()
        assert laser.wait_for_reading(3, timeout=3.0)
        scan = emulator.last_scan
        emulator.muted = True
        until = time.monotonic() + 1.0
        while time.monotonic() < until:           # a second of scans back to back
            emulator._transport.write(scan * 20)
        silent_from = time.monotonic()
        down_at = wait_until(lambda: not laser.link_up, 10.0)
        assert down_at is not None, "silence after the flood was never noticed"
        print(f"laser: link down {(down_at - silent_from) * 1000:.0f} ms after the last byte "
              f"(stale after {laser.stale_after:.2f} s)")
        assert down_at - silent_from <= NOTICED_WITHIN
        assert laser.parser.stats.packets > 100
    finally:
        laser.close()
        emulator.close()


# -- CAN: two CiA 402 drives on python-can's virtual bus, and through a socketcand server -------



def babble_frames(count: int) -> bytes:
    """Both drives' heartbeats and the sonar board's ranges, `count` frames stamped now."""
    stamp = f"{time.time():.6f}"
    frames = [f"< frame {ident} {stamp} {data} >".encode("ascii")
              for ident, data in (("701", "05"), ("702", "05"), ("190", "E803E803E803E803"))]
    return b"".join(frames[k % 3] for k in range(count))


class BabblingLink:
    """A TCP relay between the driver and a socketcand server that can, on request, stop
    relaying the server and send the driver both drives' heartbeats back to back instead
    (5000 in one write, or for 1 s): a socketcand link that floods, then falls silent."""

    def __init__(self, server: tuple[str, int]) -> None:
        import socket
        import threading
        self.server = server
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.url = "socketcand:127.0.0.1:%d" % self.listener.getsockname()[1]
        self.cut = threading.Event()
        self.client = None
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        import socket
        import threading
        client, _ = self.listener.accept()
        upstream = socket.create_connection(self.server)
        self.client = client
        for src, dst in ((client, upstream), (upstream, client)):
            threading.Thread(target=self._pipe, args=(src, dst), daemon=True).start()

    def _pipe(self, src, dst) -> None:
        while True:
            try:
                data = src.recv(65536)
            except OSError:
                return
            if not data:
                return
            if not self.cut.is_set():
                try:
                    dst.sendall(data)
                except OSError:
                    return

    def babble(self, how: str) -> float:
        """Cut the server off, flood the driver; returns when the last byte was written."""
        self.cut.set()
        if how == "5000 queued heartbeats":
            self.client.sendall(babble_frames(5000))
        else:
            until = time.monotonic() + 1.0
            while time.monotonic() < until:
                self.client.sendall(babble_frames(600))
        return time.monotonic()


def babble_on_the_bus(channel: str, how: str) -> float:
    """Both drives' heartbeats and the sonar board's ranges back to back on the virtual bus;
    returns when the last was sent."""
    import can
    from robots.canopen import protocol as cp
    frames = [can.Message(arbitration_id=can_id, data=data, is_extended_id=False)
              for can_id, data in (cp.heartbeat(1, cp.NodeState.OPERATIONAL),
                                   cp.heartbeat(2, cp.NodeState.OPERATIONAL),
                                   (0x190, bytes.fromhex("E803E803E803E803")))]
    bus = can.Bus(interface="virtual", channel=channel)
    try:
        count = 5000 if how == "5000 queued heartbeats" else None
        until = time.monotonic() + 1.0
        k = 0
        while (k < count) if count else (time.monotonic() < until):
            bus.send(frames[k % 3])
            k += 1
        return time.monotonic()
    finally:
        bus.shutdown()


@pytest.mark.parametrize("transport", ["virtual", "socketcand"])
@pytest.mark.parametrize("how", ["5000 queued heartbeats", "1 s of flooding"])
def test_canopen_notices_silence_after_a_flood(transport, how):
    from robots.canopen.driver import CanOpenBase
    argos, clock, emulator = argos_drives_in_real_time()
    link = None
    if transport == "socketcand":
        link = BabblingLink(emulator.serve_socketcand())
        url = link.url
    else:
        url = f"virtual:{emulator.channel}"
    base = CanOpenBase(argos.limits, url, clock=clock, config=emulator.config)
    try:
        base.open()
        assert base.read_state().link_up
        if link is not None:
            silent_from = link.babble(how)
        else:
            for node in emulator.drives:       # the drives fall silent; their babble is queued
                emulator.power_off(node)
            silent_from = babble_on_the_bus(emulator.channel, how)
        down_at = wait_until(lambda: not base.read_state().link_up, 10.0)
        assert down_at is not None, f"silence after {how} was never noticed"
        print(f"{transport}, {how}: fault {(down_at - silent_from) * 1000:.0f} ms after the "
              f"last frame: {base.fault}")
        assert down_at - silent_from <= NOTICED_WITHIN
        assert "no heartbeat" in base.fault
    finally:
        base.close()
        emulator.close()
