"""Guiding: watch the person who follows the robot, and keep the guide's state for the graph.

While the robot leads someone (GuidePerson), that person walks *behind* it, where the laser
does not look and the camera (240°) barely does. So the follower is estimated from two sources,
each tick:

1. the guided user's own people track, while the tracker keeps it (at the start the user
   stands in front of the robot; once behind it the camera loses them within seconds);
2. else the nearest of: a confirmed track behind the robot (more than 90° off the way it leads,
   within `reach`), and
3. the sonars looking back (more than 110° off the way): an echo whose end point lies more than
   0.25 m from every wall of the map is something standing in the open behind the robot; the
   nearest one counts, at its range plus a person's body radius.

An echo counts only when the end points of three rays across the sonar's cone (its axis and
both edges) all lie in the open: an echo off a wall at the cone's edge is the map's. Other people walking
behind the robot look like the follower to both sources (a known limit).

The behavior owns the decisions (lead, stop and wait, give up); this skill owns the state that
conditions read (`guide/state`) and the log event of a finished guide run (`guide`, with
place, outcome, reason and duration), which the application records in its database.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from robots.profile import SonarSpec
from skills.localization import Localization
from skills.navigation.gridmap import GridMap
from skills.perception import PeoplePerception
from skills.skill import Skill
from skills.status import IDLE, RUNNING, SUCCEEDED, failed

# phases (GuideState.phase)
IDLE_PHASE = "idle"
LEADING = "leading"          # driving towards the place with the user behind
WAITING = "waiting"          # stopped: the user fell behind (or is not seen)
ARRIVED = "arrived"          # at the place, arrival announced
GAVE_UP = "gave up"          # the user did not come (or the way failed)

# outcomes of a guide run (the `guide` event, the log table)
OUTCOME_ARRIVED = "arrived"
OUTCOME_USER_LOST = "user lost"
OUTCOME_NAVIGATION = "navigation failed"
OUTCOME_CANCELLED = "cancelled"

BEHIND = math.radians(90)          # a track this far off the way is behind the robot
REAR_SONAR = math.radians(110)     # sonars pointing this far off the way look back
OPEN_SPACE = 0.25                  # m from every wall: an echo there is not the map's
BODY_RADIUS = 0.2                  # m, a person's body circle (sonar echoes come off its front)
SONAR_REACH = 4.0                  # m; farther rear echoes are too wide to tell a person
FORGET_AFTER = 1.0                 # s unseen after which user_distance is absent


@dataclass(frozen=True)
class GuideState:
    """What the guide is doing, as values (`guide/state`)."""
    phase: str = IDLE_PHASE
    place: str = ""
    user_distance: float | None = None    # m, robot centre to the follower's centre
    user_bearing: float | None = None     # rad in the robot frame (pi: straight behind)
    user_xy: tuple[float, float] | None = None   # m, map frame
    source: str = ""                      # "track", "sonar" or "" (not seen)
    unseen_for: float = 0.0               # s since the follower was last seen
    waiting_for: float = 0.0              # s since the robot stopped to wait (0 when leading)
    outcome: str = ""                     # when finished: one of the OUTCOME_ values
    reason: str = ""


class Guiding(Skill):
    name = "guide"

    def __init__(self, blackboard, events, localization: Localization,
                 perception: PeoplePerception, grid: GridMap | None,
                 sonar: SonarSpec | None, reach: float = 5.0) -> None:
        super().__init__(blackboard, events)
        self.localization = localization
        self.perception = perception
        self.grid = grid
        self.reach = reach
        poses = sonar.poses if sonar is not None else np.zeros((0, 3))
        self._sonar_poses = poses
        self._cone = sonar.cone if sonar is not None else 0.0
        self.state = GuideState()
        self.user_id: int | None = None
        self._started = 0.0
        self._seen_at: float | None = None
        self._waiting_since: float | None = None
        self._forward: float | None = None     # heading while leading: what "behind" means

    # -- the API for behaviors -------------------------------------------------------------

    @property
    def active(self) -> bool:
        return self.state.phase in (LEADING, WAITING)

    def start(self, place: str, now: float, user_id: int | None = None) -> None:
        """Begin a guide run to `place`; `user_id` is the track of the person being guided
        (None: whoever is nearest behind)."""
        self.user_id = user_id
        self._started = now
        self._seen_at = now
        self._waiting_since = None
        self._forward = None
        self.state = GuideState(LEADING, place)
        self.set_status(RUNNING, now)
        self.sense(now)

    def lead(self, now: float) -> None:
        """The robot drives on (the user is close enough)."""
        if self.state.phase == WAITING:
            self._waiting_since = None
            self.state = replace(self.state, phase=LEADING, waiting_for=0.0)
            self._publish(now)

    def wait(self, now: float) -> None:
        """The robot stopped to let the user catch up."""
        if self.state.phase == LEADING:
            self._waiting_since = now
            self.state = replace(self.state, phase=WAITING)
            self._publish(now)

    def finish(self, outcome: str, now: float, reason: str = "") -> None:
        """End the run with `outcome` (OUTCOME_...); logs it once (a `guide` event)."""
        if not self.active:
            return
        phase = ARRIVED if outcome == OUTCOME_ARRIVED else GAVE_UP
        self.state = replace(self.state, phase=phase, outcome=outcome, reason=reason,
                             waiting_for=0.0)
        self.set_status(SUCCEEDED if phase == ARRIVED else failed(f"{outcome}: {reason}"), now)
        self.events.emit(now, "guide", place=self.state.place, outcome=outcome, reason=reason,
                         duration=round(now - self._started, 2))
        self._publish(now)

    def cancel(self, now: float) -> None:
        """Stop watching; a run still going is logged as cancelled."""
        if self.active:
            self.finish(OUTCOME_CANCELLED, now, "the guide was switched off")
        self.state = GuideState()
        self.user_id = None
        self.set_status(IDLE, now)
        self._publish(now)

    # -- the tick --------------------------------------------------------------------------

    def sense(self, now: float) -> None:
        if not self.active:
            return
        pose = self.localization.state
        if pose is None:
            return
        if self.state.phase == LEADING and abs(pose.v) > 0.05:
            self._forward = pose.th     # a robot turned round to look keeps its way's "behind"
        seen = self._own_track(pose)
        if seen is None:       # the nearest of a track behind the robot and a rear echo
            found = [f for f in (self._track_behind(pose), self._from_sonar(pose)) if f]
            seen = min(found, key=lambda f: f[0], default=None)
        if seen is not None:
            self._seen_at = now
            distance, bearing, xy, source = seen
            self.state = replace(self.state, user_distance=distance, user_bearing=bearing,
                                 user_xy=xy, source=source, unseen_for=0.0)
        else:
            unseen = now - (self._seen_at if self._seen_at is not None else now)
            keep = unseen < FORGET_AFTER
            self.state = replace(self.state, unseen_for=unseen, source="",
                                 user_distance=self.state.user_distance if keep else None,
                                 user_bearing=self.state.user_bearing if keep else None,
                                 user_xy=self.state.user_xy if keep else None)
        if self._waiting_since is not None:
            self.state = replace(self.state, waiting_for=now - self._waiting_since)
        self._publish(now)

    def _own_track(self, pose):
        """The guided user's own track, while the tracker still has it."""
        own = next((t for t in self.perception.tracks if t.id == self.user_id), None)
        return None if own is None else _seen(own, pose)

    def _track_behind(self, pose):
        """The nearest confirmed track behind the robot within reach."""
        behind = [t for t in self.perception.tracks if abs(self._off_way(t.x, t.y, pose)) > BEHIND
                  and math.hypot(t.x - pose.x, t.y - pose.y) <= self.reach]
        nearest = min(behind, key=lambda t: math.hypot(t.x - pose.x, t.y - pose.y), default=None)
        return None if nearest is None else _seen(nearest, pose)

    def _from_sonar(self, pose):
        if self.grid is None or not len(pose.sonar) or not len(self._sonar_poses):
            return None
        ranges = np.asarray(pose.sonar, dtype=float)[: len(self._sonar_poses)]
        poses = self._sonar_poses[: len(ranges)]
        forward = pose.th if self._forward is None else self._forward
        off_way = poses[:, 2] + pose.th - forward
        rear = np.abs(np.arctan2(np.sin(off_way), np.cos(off_way))) >= REAR_SONAR
        use = rear & np.isfinite(ranges) & (ranges <= SONAR_REACH)
        if not use.any():
            return None
        r, p = ranges[use], poses[use]
        c, s = math.cos(pose.th), math.sin(pose.th)
        open_ = np.ones(len(r), dtype=bool)
        for edge in (-0.5, 0.0, 0.5):            # the cone's edges and its axis
            a = p[:, 2] + edge * self._cone
            lx, ly = p[:, 0] + r * np.cos(a), p[:, 1] + r * np.sin(a)
            wx, wy = pose.x + c * lx - s * ly, pose.y + s * lx + c * ly
            open_ &= self.grid.clearance(wx, wy) > OPEN_SPACE
        if not open_.any():
            return None
        lx, ly = p[:, 0] + r * np.cos(p[:, 2]), p[:, 1] + r * np.sin(p[:, 2])
        d = np.hypot(lx, ly)
        d[~open_] = np.inf
        i = int(np.argmin(d))
        bearing = math.atan2(ly[i], lx[i])
        centre = d[i] + BODY_RADIUS
        x = pose.x + centre * math.cos(pose.th + bearing)
        y = pose.y + centre * math.sin(pose.th + bearing)
        return float(centre), bearing, (x, y), "sonar"

    def _off_way(self, x: float, y: float, pose) -> float:
        """Bearing of (x, y) from the robot, relative to the way it leads (its heading while
        driving; a robot that turned round to look for the user still counts its way)."""
        forward = pose.th if self._forward is None else self._forward
        a = math.atan2(y - pose.y, x - pose.x) - forward
        return math.atan2(math.sin(a), math.cos(a))

    def _publish(self, now: float) -> None:
        self.write("guide/state", self.state, now)


def _seen(track, pose):
    return (math.hypot(track.x - pose.x, track.y - pose.y), _bearing(track.x, track.y, pose),
            (track.x, track.y), "track")


def _bearing(x: float, y: float, pose) -> float:
    a = math.atan2(y - pose.y, x - pose.x) - pose.th
    return math.atan2(math.sin(a), math.cos(a))


__all__ = ["Guiding", "GuideState", "IDLE_PHASE", "LEADING", "WAITING", "ARRIVED", "GAVE_UP",
           "OUTCOME_ARRIVED", "OUTCOME_USER_LOST", "OUTCOME_NAVIGATION", "OUTCOME_CANCELLED"]
