"""Percepts from the blackboard: stale entries are absent; `people.new` and `user.left` count
from when the active macro-behavior (the current state) started."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from behaviors.percept_view import PerceptTracker
from skills.blackboard import Blackboard
from skills.people.track import Track


def track(track_id: int, born: float, confirmed_at: float) -> Track:
    return Track(track_id, 1.0, 0.0, 0.0, 0.0, np.eye(2) * 0.01, "confirmed", born, confirmed_at,
                 confirmed_at)


def perceive(writer, t: float, tracks: tuple, user: Track | None) -> None:
    """Write what the perception skill writes each tick."""
    writer.write("people/tracks", tracks, t)
    writer.write("people/user", user, t)
    writer.write("people/user_distance", None if user is None else 1.0, t)
    writer.write("people/user_approach", None if user is None else 0.3, t)


def test_stale_perception_reads_as_absent():
    bb = Blackboard("test")
    skills = SimpleNamespace(blackboard=bb, capabilities=frozenset({"touch_screen"}))
    writer = bb.writer("perception")
    alice = track(1, 0.0, 0.3)
    perceive(writer, 10.0, (alice,), alice)
    tracker = PerceptTracker()
    fresh = tracker.view(skills, 10.2)
    assert fresh["user.present"] and fresh["user.distance"] == 1.0 and fresh["people.count"] == 1
    assert fresh["user.approaching"]
    stale = tracker.view(skills, 10.7)      # perception stopped writing 0.7 s ago
    assert not stale["user.present"] and stale["user.distance"] is None
    assert stale["people.count"] == 0 and not stale["user.approaching"]


def test_new_people_and_left_user_count_from_the_state_entry():
    bb = Blackboard("test")
    skills = SimpleNamespace(blackboard=bb, capabilities=frozenset({"touch_screen"}))
    writer = bb.writer("perception")
    early, late = track(1, 0.0, 0.3), track(2, 5.0, 5.3)
    tracker = PerceptTracker()
    tracker.restart(2.0)                          # the state was entered at t = 2 s
    perceive(writer, 6.0, (early, late), late)
    view = tracker.view(skills, 6.0)
    assert view["people.count"] == 2 and view["people.new"] == 1 and not view["user.left"]
    perceive(writer, 7.0, (early,), None)             # the user's track is gone
    assert tracker.view(skills, 7.0)["user.left"]
    tracker.restart(8.0)                          # a new state: nobody has left it yet
    assert not tracker.view(skills, 8.0)["user.left"]
