"""`interbot emulate p2os`: prints where to connect, serves the real driver, stops on a signal."""
from __future__ import annotations

import re
import signal
import subprocess
import sys
import threading
import time

import pytest

from robots.emulate import EMULATORS, EmulateCommand, load_factory
from robots.p2os.driver import P2OSBase
from robots.p2os.emulator import P2OSEmulator
from robots.profile import load_profile

HOROS = load_profile("horos")


def start(*extra: str) -> tuple[subprocess.Popen, str]:
    proc = subprocess.Popen([sys.executable, "-c", "from applications.cli import main; "
                             "raise SystemExit(main())", "emulate", "p2os", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    match = re.search(r"connect to: (\S+)", line)
    assert match, (line, proc.stderr.read() if proc.poll() is not None else "")
    return proc, match.group(1)


def drive_briefly(url: str) -> None:
    base = P2OSBase(HOROS.limits, url, subclass="p2dx")
    try:
        base.open()
        assert base.robot_id == ("horos", "Pioneer", "p2dx")
        deadline = time.monotonic() + 3
        while base.read_state().v < 0.05 and time.monotonic() < deadline:
            base.command(0.3, 0.0)
            time.sleep(0.05)
        assert base.read_state().v >= 0.05
    finally:
        base.close()


@pytest.mark.parametrize("where", [("--pty",), ("--tcp", "0")])
def test_emulate_serves_the_driver_and_stops_on_a_signal(where):
    proc, url = start(*where)
    try:
        if where[0] == "--tcp":
            assert url.startswith("socket://127.0.0.1:")
        drive_briefly(url)
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=10)
        assert proc.returncode == 0
        assert "stopped" in out
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_registry_names_a_factory_that_builds_the_emulator():
    entry = EMULATORS["p2os"]
    assert entry.robot == "horos"
    assert load_factory(entry.factory).__func__ is P2OSEmulator.for_profile.__func__


def test_unknown_robot_is_a_usage_error(capsys):
    import argparse
    parser = argparse.ArgumentParser()
    command = EmulateCommand()
    command.add_arguments(parser)
    args = parser.parse_args(["p2os", "--robot", "nosuchbot"])
    assert command.run(args, stop=threading.Event()) == 2
    assert "unknown robot" in capsys.readouterr().err
