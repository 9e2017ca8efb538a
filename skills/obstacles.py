"""Obstacle sensing: sonar ranges (from the base), the free distance straight ahead and behind,
and the room to turn on the spot each way.

The free distance counts every sonar and laser reading that falls inside the corridor the
body sweeps when driving forward (backward); the safety arbiter stops forward (backward)
motion when it is short. A robot with no sonar facing backwards reports no free space behind
(0 m): it cannot see there, so it does not back up.

A sonar only says something lies somewhere in its cone at its range, so an echo counts as lying
on the sonar's axis, unless the laser explains it: a laser reading inside the cone at that range
(the same wall or jamb, placed precisely). Only unexplained echoes (glass, a low object) keep
the axis placement: a door jamb seen by a 40-degree sonar otherwise stood in the way of a robot
passing through the door centred.

The room to turn (`obstacles/turn_room`, rad each way) is how far a box-shaped body can turn
before a corner comes within TURN_MARGIN of a reading (`footprint.turn_room`); a round body's
turn sweeps nothing.
"""
from __future__ import annotations

import math

import numpy as np

from robots.devices import Laser
from robots.profile import RobotProfile
from skills.fastclip import clip as _clip
from skills.localization import Localization
from skills.navigation.footprint import Footprint, inside, turn_room
from skills.safety import TURN_MARGIN
from skills.skill import Skill


class ObstacleSensing(Skill):
    name = "obstacles"

    def __init__(self, blackboard, events, profile: RobotProfile, localization: Localization,
                 laser: Laser | None) -> None:
        super().__init__(blackboard, events)
        self.localization = localization
        self.laser = laser
        self.footprint = Footprint.of(profile)
        self.half_width = profile.width / 2
        self.front = profile.length / 2 if profile.shape == "rectangle" else profile.radius
        sonar = profile.sonar
        self._sonar_poses = sonar.poses if sonar is not None else np.zeros((0, 3))
        self._sees_behind = bool(np.any(np.cos(self._sonar_poses[:, 2]) < -0.5))
        self._cone = sonar.cone if sonar is not None else 0.0
        self._rear = (None, 0.0)    # the sonar readings' bytes and the free distance behind

    def _free_behind(self, ranges: np.ndarray) -> float:
        """`_free_behind_sonar`, computed again only when the readings changed (a standing
        robot's sonar hears the same walls tick after tick)."""
        key = ranges.tobytes()
        if key != self._rear[0]:
            self._rear = (key, self._free_behind_sonar(ranges))
        return self._rear[1]

    def sense(self, now: float) -> None:
        state = self.localization.state
        sonar = state.sonar if state is not None else ()
        self.write("sensors/sonar", tuple(sonar), now)
        readings = np.asarray(sonar, dtype=float)
        self.write("obstacles/rear", self._free_behind(readings), now)
        laser_points = np.zeros((0, 2))
        if self.laser is not None:
            scan = self.laser.read()
            if scan is not None:
                hit = np.isfinite(scan.ranges)
                # the beams' angles are in the robot frame already (the mount heading included)
                ranges, angles = scan.ranges[hit], scan.angles[hit]
                laser_points = np.column_stack([scan.origin[0] + ranges * np.cos(angles),
                                                scan.origin[1] + ranges * np.sin(angles)])
                # a reading within the body is the robot itself or a stray return
                laser_points = laser_points[~inside(self.footprint, laser_points)]
        ranges = readings[: len(self._sonar_poses)]
        if len(laser_points) and len(ranges):
            ranges = np.where(explained_echoes(ranges, self._sonar_poses[: len(ranges)],
                                               self._cone, laser_points), np.inf, ranges)
        free = self._free_ahead_sonar(ranges)
        if len(laser_points):
            free = min(free, self._free_ahead_points(laser_points[:, 0], laser_points[:, 1]))
        self.write("obstacles/front", free, now)
        self.write("obstacles/turn_room", self._turn_room(ranges, laser_points), now)

    def _turn_room(self, ranges, laser_points: np.ndarray) -> tuple[float, float]:
        """rad the body can turn each way before a corner nears a laser reading or an echo the
        laser does not explain (on its sonar's axis, as for the free distances)."""
        if self.footprint.is_round:
            return math.inf, math.inf
        if len(ranges):
            xs, ys = self._sonar_points(ranges)
            laser_points = np.concatenate([laser_points, np.column_stack([xs, ys])])
        return turn_room(self.footprint, laser_points, 0.0, TURN_MARGIN)

    def _free_behind_sonar(self, ranges) -> float:
        """The free distance behind from the sonars; 0 without any facing backwards, or
        before the first reading (unknown is not free)."""
        if not self._sees_behind or not len(ranges):
            return 0.0
        xs, ys = self._sonar_points(ranges)
        return self._free_ahead_points(-xs, -ys)

    def _free_ahead_sonar(self, ranges) -> float:
        if not len(ranges):
            return math.inf
        xs, ys = self._sonar_points(ranges)
        return self._free_ahead_points(xs, ys)

    def _sonar_points(self, ranges) -> tuple[np.ndarray, np.ndarray]:
        # Only the sonars the profile places count: a reading of any other (the driver should
        # have dropped it) has no pose to put it at.
        n = min(len(ranges), len(self._sonar_poses))
        r = np.asarray(ranges[:n], dtype=float)
        poses = self._sonar_poses[:n]
        echo = np.isfinite(r) & (r >= 0)
        r, poses = r[echo], poses[echo]
        xs = poses[:, 0] + r * np.cos(poses[:, 2])
        ys = poses[:, 1] + r * np.sin(poses[:, 2])
        return xs, ys

    def _free_ahead_points(self, xs: np.ndarray, ys: np.ndarray) -> float:
        """The free distance before the front of the corridor the body sweeps, padded either
        side by as much as a heading drift of PAD_DRIFT brings the body sideways by the time it
        gets there, up to CORRIDOR_PAD; a reading in the pad but not yet ahead of the front is
        beside the body, which drives past it (counted, it stopped a robot in a narrow door).
        A flat pad of CORRIDOR_PAD right at the front corner stopped HOROS in a door 0.25 m
        wider than it for many seconds: the jamb 9 cm beside its corner, with the laser's 2 cm
        noise, put readings 4-5 cm beside it, "0.00 m ahead" (issue 23's measurements)."""
        side = np.abs(ys)
        pad = _clip((xs - self.front) * PAD_SLOPE, 0.0, CORRIDOR_PAD)
        ahead = np.isfinite(xs) & (xs > 0) & (side <= self.half_width + pad) & (
            (side <= self.half_width) | (xs >= self.front))
        if not ahead.any():
            return math.inf
        return float(max(0.0, xs[ahead].min() - self.front))


CORRIDOR_PAD = 0.05         # m beyond the half width counted as in the way ahead, at most
PAD_DRIFT = math.radians(15)   # the pad widens as a drift of this heading would bring the body
PAD_SLOPE = math.tan(PAD_DRIFT)
ECHO_TOLERANCE = 0.10       # m: a laser reading this near a sonar's range explains its echo
CONE_SLACK = math.radians(5)   # beyond the cone's half angle (the cone's edge is not sharp)


def explained_echoes(ranges: np.ndarray, poses: np.ndarray, cone: float,
                     laser_points: np.ndarray) -> np.ndarray:
    """(n,) True for each sonar echo the laser explains: the nearest laser reading inside the
    sonar's cone (robot frame: `poses` x, y, heading rad; `laser_points` (k, 2)) lies within
    ECHO_TOLERANCE of the echo's range. A sonar hears the nearest thing in its cone, so such a
    reading is what it heard, placed precisely."""
    ranges = np.asarray(ranges, dtype=float)
    out = np.zeros(len(ranges), dtype=bool)
    if not len(laser_points) or not len(ranges):
        return out
    # only a sonar with an echo can be explained: the others' rows are left out (each row is
    # computed on its own, so the echoes' rows come out the same)
    echo = np.flatnonzero(np.isfinite(ranges))
    if not len(echo):
        return out
    heading = poses[:, 2]
    cos, sin = np.cos(heading)[echo, None], np.sin(heading)[echo, None]
    poses = poses[echo]
    laser_points = _within_reach(laser_points, poses, ranges[echo])
    if not len(laser_points):
        return out
    dx = laser_points[None, :, 0] - poses[:, None, 0]
    dy = laser_points[None, :, 1] - poses[:, None, 1]
    distance = np.hypot(dx, dy)
    # inside the cone: the reading's direction within the half angle of the sonar's axis,
    # tested as a projection (no angle computed per reading and sonar)
    along = dx * cos + dy * sin
    inside = along >= distance * math.cos(min(cone / 2 + CONE_SLACK, math.pi))
    nearest = np.where(inside, distance, np.inf).min(axis=1)
    out[echo] = np.abs(nearest - ranges[echo]) <= ECHO_TOLERANCE
    return out


def _within_reach(laser_points: np.ndarray, poses: np.ndarray, ranges: np.ndarray) -> np.ndarray:
    """The laser points that may decide `explained_echoes`: a point farther from the robot's
    origin than the longest echo plus ECHO_TOLERANCE plus the farthest sonar's offset (plus
    REACH_SLACK for rounding) is farther than that from every sonar, so it can neither be a
    reading within the tolerance of an echo nor lie nearer than one that is: leaving it out
    changes no answer, and saves its row of distances and projections for every sonar (a
    third of a scan in a hallway)."""
    reach = (float(ranges.max()) + ECHO_TOLERANCE + REACH_SLACK
             + float(np.hypot(poses[:, 0], poses[:, 1]).max()))
    far = np.hypot(laser_points[:, 0], laser_points[:, 1]) > reach
    return laser_points[~far] if far.any() else laser_points


REACH_SLACK = 0.01          # m: far more than the rounding of any distance computed here
