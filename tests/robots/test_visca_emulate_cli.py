"""`interbot emulate visca`: prints where to connect, serves the real head driver, stops on a signal."""
from __future__ import annotations

import math
import re
import signal
import subprocess
import sys
import time

import pytest

from robots.emulate import EMULATORS, load_factory
from robots.profile import load_profile
from robots.visca.driver import ViscaHead
from robots.visca.emulator import ViscaEmulator

HOROS = load_profile("horos")


def start(*extra: str) -> tuple[subprocess.Popen, str, str]:
    proc = subprocess.Popen([sys.executable, "-c", "from applications.cli import main; "
                             "raise SystemExit(main())", "emulate", "visca", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    match = re.search(r"connect to: (\S+)", line)
    assert match, (line, proc.stderr.read() if proc.poll() is not None else "")
    return proc, match.group(1), proc.stdout.readline()


@pytest.mark.parametrize("where", [("--pty",), ("--tcp", "0")])
def test_emulate_visca_serves_the_head_driver(where):
    proc, url, hint = start(*where)
    try:
        assert f'[head] device = "visca:{url}"' in hint
        head = ViscaHead(HOROS.head, url)
        try:
            head.open()
            head.point(math.radians(-40), 0.0)
            deadline = time.monotonic() + 3
            while abs(math.degrees(head.read()[0]) + 40) > 0.2 and time.monotonic() < deadline:
                time.sleep(0.05)
            assert math.degrees(head.read()[0]) == pytest.approx(-40, abs=0.2)
        finally:
            head.close()
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=10)
        assert proc.returncode == 0 and "stopped" in out
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_registry_names_the_visca_factory():
    entry = EMULATORS["visca"]
    assert entry.robot == "horos"
    assert load_factory(entry.factory).__func__ is ViscaEmulator.for_profile.__func__
