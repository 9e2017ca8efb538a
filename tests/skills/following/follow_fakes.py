"""Stand-ins for the follower's neighbours (pose, perception, motion) and tracks, for the
tests of its parts without a world."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.following import Following
from skills.people.track import CONFIRMED, Track


class Pose:
    def __init__(self, x, y, th):
        self.x, self.y, self.th = x, y, th


class Localization:
    def __init__(self):
        self.state = Pose(0.0, 0.0, 0.0)


class Perception:
    def __init__(self):
        self.believed = ()
        self.user = None


class Motion:
    def __init__(self):
        self.goal = None
        self.followed = None
        self.limits = limits()

    def start(self, goal, now):
        self.goal = goal

    def cancel(self, now):
        self.goal = None


def limits():
    from robots.profile import load_profile
    return load_profile("perses").limits


def track(tid, x, y, t, vx=0.0, vy=0.0, status=CONFIRMED):
    return Track(tid, x, y, vx, vy, np.eye(2) * 0.01, status, 0.0, 0.0, t)


def follower(speech=None):
    perception = Perception()
    following = Following(Blackboard("gate"), EventLog(), Localization(), perception, Motion(),
                          speech=speech)
    return following, perception


class Speech:
    def __init__(self):
        self.said = []

    def say(self, text, now):
        self.said.append((now, text))


RED = (0.55, 0.15, 0.1, 0.1, 0.05, 0.05)
BLUE = (0.05, 0.05, 0.1, 0.1, 0.15, 0.55)


def seen(tid, x, y, t, look, vx=0.0):
    return replace(track(tid, x, y, t, vx=vx), appearance=look, appearance_t=t)


def learn_her(following, perception, until=1.0):
    """Follow track 1 (in red) walking along x for `until` s; returns the next time."""
    perception.believed = (seen(1, 2.0, 0.0, 0.0, RED, vx=0.5),)
    following.follow(0.0, target=1)
    k = 0
    while k * 0.1 <= until + 1e-9:
        t = k * 0.1
        perception.believed = (seen(1, 2.0 + 0.5 * t, 0.0, t, RED, vx=0.5),)
        following.sense(t)
        k += 1
    return k * 0.1
