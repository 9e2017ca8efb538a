"""The wedge recovery's rules (skills/wedge.py), tick by tick at 10 Hz: when it backs out, for
how long, and when it never does."""
from __future__ import annotations

import math

import pytest

from skills.safety import STOP_DISTANCE
from skills.wedge import BACK_OUT_MAX, BACK_OUT_SPEED, TURN_FREED, WEDGED_AFTER, WedgeRecovery

HELD_ROOM = (0.0, 0.0)               # no room to turn either way
FREE = 2.0                           # m free behind


def ticks(recovery, count, *, v=0.0, w=0.5, room=HELD_ROOM, ahead=0.0, behind=FREE, start=0.0,
          y=0.0):
    """`count` ticks asking for (v, w); the robot backs at what it is told (y falls). Returns
    the commands and where it ended."""
    out = []
    for k in range(count):
        now = start + 0.1 * k
        command = recovery.command(v, w, room, ahead, behind, 0.0, y, now)
        out.append(command)
        y += 0.1 * min(command[0], 0.0)
    return out, y


def test_a_turn_held_for_two_seconds_backs_out_straight_once_and_no_farther_than_the_most():
    commands, y = ticks(WedgeRecovery(), 150)
    first = next(k for k, (v, _, _) in enumerate(commands) if v < 0.0)
    assert first == round(WEDGED_AFTER * 10)                        # held first, then backs
    assert all(c[:2] == (-BACK_OUT_SPEED, 0.0) for c in commands[first:first + 10])
    assert all(why.startswith("backing out") for _, _, why in commands[first:first + 10])
    assert -y == pytest.approx(BACK_OUT_MAX, abs=0.1 * BACK_OUT_SPEED)   # no farther
    last = max(k for k, (v, _, _) in enumerate(commands) if v < 0.0)
    # still held after it: it stands, asking to turn, and does not back out again
    assert all(c == (0.0, 0.5, "") for c in commands[last + 1:]) and len(commands) - last > 60


def test_a_turn_that_was_free_again_may_back_out_of_the_next_wedge():
    recovery = WedgeRecovery()
    _, y = ticks(recovery, 100)                                      # one back-out, spent
    ticks(recovery, 1, room=(1.0, 1.0), start=10.0, y=y)             # the turn was free
    commands, _ = ticks(recovery, 30, start=10.1, y=y)               # held again
    assert any(v < 0.0 for v, _, _ in commands)


def test_backing_ends_as_soon_as_the_turn_has_room():
    recovery = WedgeRecovery()
    commands, y = ticks(recovery, 25)                                # backing by now
    assert commands[-1][0] < 0.0
    (v, w, why), = ticks(recovery, 1, room=(TURN_FREED, 0.0), start=2.5, y=y)[0]
    assert (v, w, why) == (0.0, 0.5, "")


def test_never_with_too_little_room_behind_nor_while_driving_on_nor_without_a_turn():
    assert all(v >= 0.0 for v, _, _ in ticks(WedgeRecovery(), 60, behind=STOP_DISTANCE)[0])
    assert all(v > 0.0 for v, _, _ in ticks(WedgeRecovery(), 60, v=0.3, ahead=1.0)[0])
    assert all((v, w) == (0.0, 0.0) for v, w, _ in ticks(WedgeRecovery(), 60, w=0.0)[0])
    assert all(v >= 0.0 for v, _, _ in ticks(WedgeRecovery(), 60, room=(math.radians(5), 0.0))[0])
