"""`interbot emulate can`: a socketcand server on 127.0.0.1 that the real driver drives through."""
from __future__ import annotations

import re
import signal
import socket
import struct
import subprocess
import sys
import threading
import time

import pytest

from robots.canopen.driver import CanOpenBase
from robots.clock import RealClock
from robots.profile import load_profile

ARGOS = load_profile("argos")


@pytest.fixture
def server():
    proc = subprocess.Popen([sys.executable, "-c", "from applications.cli import main; "
                             "raise SystemExit(main())", "emulate", "can", "--tcp", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    match = re.search(r"connect to: (socketcand:127\.0\.0\.1:\d+)", line)
    assert match, (line, proc.stderr.read() if proc.poll() is not None else "")
    yield proc, match.group(1)
    if proc.poll() is None:
        proc.kill()
        proc.wait()


@pytest.fixture
def thread_exceptions(monkeypatch):
    """The exceptions that escape any thread during the test (none may)."""
    raised = []
    monkeypatch.setattr(threading, "excepthook", lambda args: raised.append(args.exc_value))
    return raised


def test_the_driver_drives_the_served_emulator_from_another_process(server, tmp_path):
    proc, port = server
    log = tmp_path / "session.log"
    base = CanOpenBase.for_profile(ARGOS, f"{port}?log={log}", clock=RealClock())
    try:
        base.open()
        deadline = time.monotonic() + 3
        while base.read_state().v < 0.1 and time.monotonic() < deadline:
            base.command(0.3, 0.0)
            time.sleep(0.05)
        state = base.read_state()
        assert state.link_up and state.v >= 0.1 and len(state.sonar) == 8
    finally:
        base.close()
    frames = [line.split()[2] for line in log.read_text().splitlines()]
    assert "000#8200" in frames and "701#00" in frames and any(f.startswith("181#") for f in frames)
    proc.send_signal(signal.SIGTERM)
    out, _ = proc.communicate(timeout=10)
    assert proc.returncode == 0 and "can emulator stopped" in out


def test_the_can_emulator_refuses_a_pty():
    result = subprocess.run([sys.executable, "-c", "from applications.cli import main; "
                             "raise SystemExit(main())", "emulate", "can", "--pty"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 2 and "serves TCP only; use --tcp PORT" in result.stderr


def test_emulate_can_on_a_python_can_bus_instead_of_tcp(capsys):
    """`--bus socketcan:vcan0` where a machine has vcan; here the same path on a virtual bus."""
    import argparse

    from robots.emulate import EmulateCommand

    command = EmulateCommand()
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    args = parser.parse_args(["can", "--bus", "virtual:emulate-bus-test"])
    stop = threading.Event()
    thread = threading.Thread(target=command.run, args=(args, stop), daemon=True)
    thread.start()
    deadline = time.monotonic() + 10
    while "ready" not in capsys.readouterr().out and time.monotonic() < deadline:
        time.sleep(0.05)
    base = CanOpenBase.for_profile(ARGOS, "virtual:emulate-bus-test", clock=RealClock())
    try:
        base.open()
        assert base.read_state().link_up
    finally:
        base.close()
        stop.set()
        thread.join(timeout=10)
    assert not thread.is_alive()
    with pytest.raises(SystemExit):
        parser.parse_args(["can", "--bus", "virtual:x", "--tcp", "0"])      # one or the other


def test_losing_the_socketcand_link_is_a_link_fault_not_an_exception(server, thread_exceptions):
    """The bus server dies while driving: the driver reports a fault, its threads raise
    nothing (no BrokenPipeError for the CLI to take for a closed stdout), close() returns."""
    proc, port = server
    base = CanOpenBase.for_profile(ARGOS, port, clock=RealClock())
    try:
        base.open()
        base.command(0.2, 0.0)
        proc.kill()
        proc.wait()
        deadline = time.monotonic() + 2.0
        while (base.fault is None or base.read_state().link_up) and time.monotonic() < deadline:
            base.command(0.2, 0.0)
            time.sleep(0.02)
        print(f"\nfault after the socketcand server died: {base.fault}")
        assert base.fault is not None and not base.read_state().link_up
        assert base.read_state().extra["fault_device"].startswith("CAN link socketcand:127.0.0.1")
        t0 = time.monotonic()
    finally:
        base.close()
    assert time.monotonic() - t0 < 3.0
    assert not thread_exceptions, thread_exceptions


class ResettingProxy:
    """A TCP relay between the driver and the bus server that can end the driver's side with a
    reset (RST, SO_LINGER 0): the driver then reads ConnectionResetError, not end of file."""

    def __init__(self, upstream_port: int) -> None:
        self.upstream_port = upstream_port
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.client = None
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        self.client, _ = self.listener.accept()
        upstream = socket.create_connection(("127.0.0.1", self.upstream_port))
        for a, b in ((self.client, upstream), (upstream, self.client)):
            threading.Thread(target=self._pump, args=(a, b), daemon=True).start()

    @staticmethod
    def _pump(src, dst) -> None:
        try:
            while chunk := src.recv(4096):
                dst.sendall(chunk)
        except OSError:
            pass

    def reset(self) -> None:
        self.client.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        self.client.close()
        self.listener.close()


def test_a_reset_link_is_a_link_fault_and_no_thread_raises(server, thread_exceptions):
    """The receive thread reads 'connection reset' (seen once in the suite when the server was
    killed): the driver takes it as a link fault; canopen's receive thread must not re-raise it."""
    _, port = server
    proxy = ResettingProxy(int(port.rsplit(":", 1)[1]))
    base = CanOpenBase.for_profile(ARGOS, f"socketcand:127.0.0.1:{proxy.port}", clock=RealClock())
    try:
        base.open()
        base.command(0.2, 0.0)
        proxy.reset()
        deadline = time.monotonic() + 2.0
        # no command: the receive side alone must see it. The fault shows before the state's
        # link_up goes false (the quick stop is sent in between): wait for both.
        while ((base.fault is None or base.read_state().link_up)
               and time.monotonic() < deadline):
            time.sleep(0.01)
        assert base.fault is not None and not base.read_state().link_up, base.fault
        assert "CAN link lost" in base.fault         # seen by the receive thread or a send
        assert base.read_state().extra["fault_device"].startswith("CAN link socketcand:127.0.0.1")
    finally:
        base.close()
    assert not thread_exceptions, thread_exceptions
