"""Stand-ins for the follower's neighbours (pose, perception, motion) and tracks, for the
tests of its parts without a world."""
from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np

from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.following import Following
from skills.people.track import CONFIRMED, Track
from skills.status import IDLE


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
        self.people_near = False      # someone the near-people cap is for is near the robot

    def top_speed(self):
        if self.people_near:
            return min(self.limits.max_speed, self.limits.max_speed_near_people)
        return self.limits.max_speed

    def start(self, goal, now):
        self.goal = goal

    def cancel(self, now):
        self.goal = None


def limits():
    from robots.profile import load_profile
    return load_profile("perses").limits


def track(tid, x, y, t, vx=0.0, vy=0.0, status=CONFIRMED, camera_seen=None):
    """A track last seen at `t`, by the camera then too unless `camera_seen` says when."""
    return Track(tid, x, y, vx, vy, np.eye(2) * 0.01, status, 0.0, 0.0, t,
                 confirmed_seen=t if camera_seen is None else camera_seen)


def follower(speech=None):
    perception = Perception()
    following = Following(Blackboard("gate"), EventLog(), Localization(), perception, Motion(),
                          speech=speech)
    return following, perception


class Speech:
    def __init__(self):
        self.said = []
        self.status = SimpleNamespace(running=False)     # never still speaking

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


class ShelfGrid:
    """A map with one shelf face along x = `shelf_x` (free for x below it): the clearance is
    the distance to that face (negative inside the shelf)."""

    def __init__(self, shelf_x: float):
        self.shelf_x = shelf_x
        self.places = {}
        self.bounds = (-5.0, -5.0, shelf_x + 1.0, 5.0)

    def clearance(self, x, y):
        return self.shelf_x - np.asarray(x, dtype=float) + 0.0 * np.asarray(y, dtype=float)

    def clearance_at(self, x: float, y: float) -> float:
        """`clearance` of one point, as GridMap.clearance_at answers it."""
        return float(self.clearance(x, y))


class Navigation:
    """Navigation that records its goals and never moves (for tests without a world)."""

    def __init__(self, grid):
        from robots.profile import load_profile
        self.grid = grid
        self.profile = load_profile("perses")
        self.limits = self.profile.limits
        self.state = SimpleNamespace(phase="idle")
        self.status = IDLE
        self.ignore_people = frozenset()
        self.goals = []

    def go_to(self, goal, now, speed=None):
        self.goals.append(goal)
        self.state.phase = "driving"

    def set_speed(self, speed):
        pass

    def cancel(self, now):
        self.state.phase = "idle"
