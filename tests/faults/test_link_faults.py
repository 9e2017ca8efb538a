"""`interbot run --port` against a robot end that misbehaves: silent, garbage, closed, flooding,
absurd. For each: no traceback, the robot end gets a stop where the link can still carry one,
the first command after a re-connect is a stop, the episode is in the trace and the summary,
the behaviors saw `robot.fault` while it lasted, and the trace is whole."""
from __future__ import annotations

import time
from dataclasses import replace

import pytest

from tests.faults.conftest import (commands_after_open, first_stop_after, record_delay, wait)


def assert_clean_exit(finished) -> None:
    assert "Traceback" not in finished.err and "Traceback" not in finished.out
    assert finished.code == 0, finished.err
    assert "ran " in finished.out                       # the summary was printed


def assert_trace_whole(finished) -> None:
    """Every line parsed (the fixture would have raised), starting with the initial state."""
    assert finished.trace[0]["kind"] == "transition" and finished.trace[0]["to"] == "Wait"
    assert all("t" in e and "kind" in e for e in finished.trace)


def link_events(finished) -> list[dict]:
    return [e for e in finished.trace if e["kind"] == "link"]


def assert_episode_recorded(finished, reason_part: str) -> None:
    events = link_events(finished)
    assert [e["state"] for e in events][:2] == ["down", "up"], events
    assert reason_part in events[0]["reason"]
    assert events[1]["after"] > 0
    assert "link to the base: down 1 time(s), re-connected 1 time(s)" in finished.out
    assert finished.err.count("link down") == 1, finished.err      # once per episode
    # the run's own time line says it too, in order with the transitions
    assert finished.out.count("LINK DOWN: ") == 1 and "link back up after" in finished.out
    # The behaviors saw it: the application went to Halted while robot.fault held, and back.
    moves = [(e["from"], e["to"]) for e in finished.trace if e["kind"] == "transition"]
    assert ("Wait", "Halted") in moves and ("Halted", "Wait") in moves
    assert moves.count(("Wait", "Halted")) == 1         # robot.fault held through the episode
    halted_at = next(e["t"] for e in finished.trace
                     if e["kind"] == "transition" and e["to"] == "Halted")
    assert halted_at >= events[0]["t"] - 0.2


def assert_reconnect_starts_with_a_stop(peer) -> None:
    assert peer.connections >= 2
    after_open = commands_after_open(peer, 2)
    assert after_open[:2] == ["VEL 0", "RVEL 0"], after_open


@pytest.mark.parametrize("mode,seconds,reason", [("silent", 3.0, "no SIP"),
                                                 ("garbage", 2.0, "no SIP")])
def test_a_silent_or_garbling_robot_gets_a_stop_and_the_episode_is_recorded(
        peer, start_run, mode, seconds, reason):
    run = start_run(peer, duration=9)
    wait(1.5)
    fault_at = time.monotonic()
    peer.mode = mode
    wait(seconds)
    peer.mode = "normal"
    finished = run.finish()
    assert_clean_exit(finished)
    stop = first_stop_after(peer, fault_at, conn=1)
    assert stop is not None, "the old connection still carried bytes, but no stop came"
    record_delay(mode, stop.t - fault_at)
    assert_reconnect_starts_with_a_stop(peer)
    assert_episode_recorded(finished, reason)
    assert_trace_whole(finished)


def test_a_robot_that_closes_its_socket_is_reconnected_starting_with_a_stop(peer, start_run):
    run = start_run(peer, duration=6)
    wait(1.5)
    peer.close()
    finished = run.finish()
    assert_clean_exit(finished)
    assert_reconnect_starts_with_a_stop(peer)
    assert_episode_recorded(finished, "base link is down")
    assert_trace_whole(finished)


def test_a_flooding_robot_does_not_stop_the_run(peer, start_run):
    run = start_run(peer, duration=5)
    wait(1.0)
    flood_at = time.monotonic()
    peer.mode = "flood"
    wait(2.0)
    peer.mode = "normal"
    finished = run.finish()
    assert_clean_exit(finished)
    # The driver kept its keep-alive going through the flood (a zero every 0.5 s)...
    during = [r for r in list(peer.received)
              if flood_at <= r.t <= flood_at + 2.0 and r.name == "VEL 0"]
    assert len(during) >= 2
    # ...and ended with a stop and CLOSE.
    assert peer.names()[-3:] == ["VEL 0", "RVEL 0", "CLOSE"]
    assert_trace_whole(finished)


def test_absurd_but_well_formed_packets_are_dropped_and_counted_not_a_crash(peer, start_run):
    run = start_run(peer, duration=4)
    wait(1.0)
    # 32 sonar readings for a 16-sonar profile, ranges far beyond the sensor, absurd wheels.
    peer.sip = replace(peer.sip, sonar=tuple((i, 65535 if i % 2 else 1000) for i in range(32)),
                       lvel=32767, rvel=-32768, battery=0)
    finished = run.finish()
    assert_clean_exit(finished)
    dropped = [e for e in finished.trace if e["kind"] == "dropped"]
    assert dropped and sum(e["count"] for e in dropped) == dropped[-1]["total"]
    assert any("sonar number" in e["reason"] for e in dropped)
    assert f"readings dropped (not described by the robot profile): {dropped[-1]['total']}" \
        in finished.out
    assert peer.names()[-3:] == ["VEL 0", "RVEL 0", "CLOSE"]
    assert_trace_whole(finished)
