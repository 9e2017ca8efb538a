"""SIGTERM (`systemctl stop`, `docker stop`), SIGHUP (a closed terminal) and SIGINT (Ctrl-C) end
a real `interbot run --port` process the same way: the robot end receives a stop and CLOSE, the
summary is printed, stderr has one line, and the exit code is 128 + the signal's number."""
from __future__ import annotations

import signal

import pytest

from tests.faults.conftest import wait


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_signal_stops_and_closes_the_robot_and_prints_the_summary(peer, start_run, signum):
    run = start_run(peer, duration=60)
    wait(1.5)
    sent_before = len(peer.received)
    run.process.send_signal(signum)
    finished = run.finish(timeout=20)
    assert finished.code == 128 + signum
    after = [r.name for r in list(peer.received)[sent_before:]]
    assert "VEL 0" in after and "RVEL 0" in after
    assert after[-1] == "CLOSE"
    assert after.index("VEL 0") < after.index("CLOSE")
    assert "ran " in finished.out and "answers recorded" in finished.out
    name = "SIGINT" if signum == signal.SIGINT else signal.Signals(signum).name
    assert f"ended early by {name}" in finished.out
    err = finished.err.strip().splitlines()
    assert len(err) == 1 and "interrupted by" in err[0], finished.err
    assert "Traceback" not in finished.err
