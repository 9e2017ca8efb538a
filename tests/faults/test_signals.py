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


def test_a_link_lost_just_before_a_signal_is_in_the_trace_and_the_summary(peer, start_run):
    """The robot end hangs up and a SIGTERM follows at once, before a tick could report the
    episode: the closing still records it (and that no stop could be sent) in the trace and
    the summary, not only on stderr."""
    run = start_run(peer, duration=60)
    wait(1.5)
    peer.mode = "silent"                       # reconnecting finds nobody who answers
    peer.close()
    wait(0.03)
    run.process.send_signal(signal.SIGTERM)
    finished = run.finish(timeout=20)
    assert finished.code == 128 + signal.SIGTERM
    downs = [e for e in finished.trace if e["kind"] == "link" and e["state"] == "down"]
    assert downs, [e["kind"] for e in finished.trace]
    assert downs[0]["base"].startswith("P2OS controller on socket://")
    assert any(e["reason"].startswith("while closing: no stop could be sent, the link was down")
               for e in downs), downs
    assert "link to the base: down" in finished.out and "down at the end" in finished.out
    assert "while closing: no stop could be sent" in finished.out
