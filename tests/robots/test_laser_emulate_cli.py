"""`interbot emulate lms200|urg`: the laser emulators on a pty or TCP, read by their drivers."""
from __future__ import annotations

import re
import signal
import subprocess
import sys

import numpy as np
import pytest

from robots.emulate import EMULATORS, load_factory
from robots.hokuyo.driver import HokuyoLaser
from robots.hokuyo.emulator import HokuyoEmulator
from robots.lms2xx.driver import LMS2xxLaser
from robots.lms2xx.emulator import LMS2xxEmulator
from robots.profile import load_profile

DRIVERS = {"lms200": lambda url: LMS2xxLaser.for_profile(load_profile("horos"), url),
           "urg": lambda url: HokuyoLaser.for_profile(load_profile("argos"), url)}


def start(name: str, *extra: str) -> tuple[subprocess.Popen, str, str]:
    proc = subprocess.Popen([sys.executable, "-c", "from applications.cli import main; "
                             "raise SystemExit(main())", "emulate", name, *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    hint = proc.stdout.readline()
    match = re.search(r"connect to: (\S+)", line)
    assert match, (line, proc.stderr.read() if proc.poll() is not None else "")
    return proc, match.group(1), hint


@pytest.mark.parametrize("name", sorted(DRIVERS))
@pytest.mark.parametrize("where", [("--pty",), ("--tcp", "0")])
def test_emulate_serves_the_laser_driver_and_stops_on_a_signal(name, where):
    proc, url, hint = start(name, *where)
    try:
        assert f'[laser] device = "{name}:{url}" in the robot profile' in hint
        laser = DRIVERS[name](url)
        try:
            laser.open()
            assert laser.wait_for_reading(0, timeout=3.0)
            scan = laser.read()
            assert np.isfinite(scan.ranges).sum() > len(scan.ranges) // 2   # walls in the office
        finally:
            laser.close()
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=10)
        assert proc.returncode == 0 and "stopped" in out
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_registry_names_the_laser_factories():
    assert load_factory(EMULATORS["lms200"].factory).__func__ is \
        LMS2xxEmulator.for_profile.__func__
    assert load_factory(EMULATORS["urg"].factory).__func__ is \
        HokuyoEmulator.for_profile.__func__
