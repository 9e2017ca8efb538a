"""Guiding: watch the person who follows the robot, and keep the guide's state for the graph.

While the robot leads someone (GuidePerson), that person walks *behind* it, where the laser
does not look and the camera (240°) barely does. So the follower is estimated from two sources,
each tick:

1. a confirmed people track: the guided user's own track while it lives, else the nearest
   track behind the robot (more than 90° off its heading, within `reach`), which then becomes
   the followed track;
2. the rear sonars (more than 110° off the heading): an echo whose end point lies more than
   0.25 m from every wall of the map is something standing in the open behind the robot; the
   nearest one counts, at its range plus a person's body radius.

The track wins when there is one; sonar covers the blind cone behind. Other people walking
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

BEHIND = math.radians(90)          # a track this far off the heading is behind the robot
REAR_SONAR = math.radians(110)     # sonars pointing this far off the heading look back
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
        self._rear = np.abs(np.arctan2(np.sin(poses[:, 2]), np.cos(poses[:, 2]))) >= REAR_SONAR
        self._sonar_poses = poses
        self.state = GuideState()
        self.user_id: int | None = None
        self._started = 0.0
        self._seen_at: float | None = None
        self._waiting_since: float | None = None

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
        seen = self._from_track(pose) or self._from_sonar(pose)
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

    def _from_track(self, pose):
        tracks = self.perception.tracks
        own = next((t for t in tracks if t.id == self.user_id), None)
        if own is None:
            behind = [t for t in tracks if abs(_bearing(t.x, t.y, pose)) > BEHIND
                      and math.hypot(t.x - pose.x, t.y - pose.y) <= self.reach]
            own = min(behind, key=lambda t: math.hypot(t.x - pose.x, t.y - pose.y), default=None)
            if own is None:
                return None
            self.user_id = own.id
        distance = math.hypot(own.x - pose.x, own.y - pose.y)
        return distance, _bearing(own.x, own.y, pose), (own.x, own.y), "track"

    def _from_sonar(self, pose):
        if self.grid is None or not len(pose.sonar) or not self._rear.any():
            return None
        ranges = np.asarray(pose.sonar, dtype=float)[: len(self._sonar_poses)]
        poses = self._sonar_poses[: len(ranges)]
        use = self._rear[: len(ranges)] & np.isfinite(ranges) & (ranges <= SONAR_REACH)
        if not use.any():
            return None
        r, p = ranges[use], poses[use]
        lx = p[:, 0] + r * np.cos(p[:, 2])
        ly = p[:, 1] + r * np.sin(p[:, 2])
        c, s = math.cos(pose.th), math.sin(pose.th)
        wx, wy = pose.x + c * lx - s * ly, pose.y + s * lx + c * ly
        open_ = self.grid.clearance(wx, wy) > OPEN_SPACE
        if not open_.any():
            return None
        d = np.hypot(lx, ly)
        d[~open_] = np.inf
        i = int(np.argmin(d))
        bearing = math.atan2(ly[i], lx[i])
        centre = d[i] + BODY_RADIUS
        x = pose.x + centre * math.cos(pose.th + bearing)
        y = pose.y + centre * math.sin(pose.th + bearing)
        return float(centre), bearing, (x, y), "sonar"

    def _publish(self, now: float) -> None:
        self.write("guide/state", self.state, now)


def _bearing(x: float, y: float, pose) -> float:
    a = math.atan2(y - pose.y, x - pose.x) - pose.th
    return math.atan2(math.sin(a), math.cos(a))


__all__ = ["Guiding", "GuideState", "IDLE_PHASE", "LEADING", "WAITING", "ARRIVED", "GAVE_UP",
           "OUTCOME_ARRIVED", "OUTCOME_USER_LOST", "OUTCOME_NAVIGATION", "OUTCOME_CANCELLED"]
