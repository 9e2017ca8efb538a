"""Guiding: watch the person who follows the robot, and keep the guide's state for the graph.

While the robot leads someone (GuidePerson), that person walks *behind* it, where the laser
does not look and the camera (240°) barely does. So the follower is estimated each tick as the
nearest of:

1. the guided user's own people track, while the tracker keeps it and no wall of the map is in
   between (at the start the user stands in front of the robot; once behind it the camera
   loses them within seconds, and the track may jump onto a leg-like return ahead: it does not
   outrank a nearer sighting behind);
2. a confirmed track behind the robot (more than 90° off the way it leads, that is the
   direction of its path; in any direction within 1 m of the goal), within `reach` and with
   no wall of the map in between;
3. the sonars looking back (more than 110° off the way): an echo that no wall of the map
   explains is something standing in the open behind the robot; the nearest one counts, at
   its range plus a person's body radius;
4. failing those, the last sighting, for up to 6 s, while the place it puts the follower (as
   far behind, as far off the way) is where no sensor of the robot looks or behind a wall of
   the map (round a corner, where nothing sees them): ARGOS has no sonar
   behind, so it turns round to look, sees its visitor and turns back to the way; without
   this it lost them at once and stopped again a few decimetres on.

A wall explains an echo when any of five rays across the sonar's cone meets it no farther
than 0.10 m beyond the echo's range, per echo across the part of the cone that matters: a
person standing in a doorway, with the jambs a body's depth behind their front, is not the
wall's echo (with 0.25 m they were, and a visitor waiting in a doorway was "lost"). Behind the
laser the rays span ±cone/3, where a sonar hears walls (the cone's edge meets them at a
glancing angle that returns nothing): in a 1 m hallway the rays to ±15° met the walls 1.0 m
from a rear sonar and "explained" the echo of a visitor 1.5 m straight behind (1.04 m; the
walls are heard 1.38 m away). Where the laser looks the rays span the whole cone: the laser
and camera find a person there, so the sonar must be sure (ARGOS, turned round to look with
its front sonars, took wall echoes at its cones' edges for a visitor who had left). The span
is widened by the turn the robot makes in one tick, since an echo may be that old.
Other people walking behind the robot look like the follower to these sources (a known
limit). In a 1 m hallway a visitor more than about 1.8 m straight behind HOROS is hidden by
the walls' echo: its rear sonars read what they read in the empty hallway, so this skill cannot
see them; GuidePerson's `Lead` turns the robot round to look for a visitor it does not see.

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
BODY_RADIUS = 0.2                  # m, a person's body circle (sonar echoes come off its front)
SONAR_REACH = 3.0                  # m; farther rear echoes are too wide to tell a person
HEARD = 1 / 3                      # of the cone either side of its axis, where a sonar hears walls
SONAR_AGE = 0.1                    # s an echo may be old (one tick): turning, its heading is off
MARCH_STEP = 0.05                  # m between the points checked along a ray
WALL_SLACK = 0.10                  # m beyond the echo a wall may be and still explain it
WALL_HIT = 0.08                    # m: a ray point this close to a wall has met it
AHEAD = 0.5                        # m along the path ahead of the robot that gives its way
NEAR_GOAL = 1.0                    # m left: around the goal a track counts in any direction
FORGET_AFTER = 1.0                 # s unseen after which user_distance is absent
BLIND_MEMORY = 6.0                 # s a follower last seen where no sensor looks is kept


@dataclass(frozen=True)
class GuideState:
    """What the guide is doing, as values (`guide/state`)."""
    phase: str = IDLE_PHASE
    place: str = ""
    user_distance: float | None = None    # m, robot centre to the follower's centre
    user_bearing: float | None = None     # rad in the robot frame (pi: straight behind)
    user_xy: tuple[float, float] | None = None   # m, map frame
    source: str = ""                      # "track", "sonar", "memory" or "" (not seen)
    unseen_for: float = 0.0               # s since the follower was last seen
    waiting_for: float = 0.0              # s since the robot stopped to wait (0 when leading)
    outcome: str = ""                     # when finished: one of the OUTCOME_ values
    reason: str = ""


class Guiding(Skill):
    name = "guide"

    def __init__(self, blackboard, events, localization: Localization,
                 perception: PeoplePerception, grid: GridMap | None,
                 sonar: SonarSpec | None, reach: float = 5.0, camera_fov: float = 0.0) -> None:
        super().__init__(blackboard, events)
        self.localization = localization
        self.perception = perception
        self.grid = grid
        self.reach = reach
        poses = sonar.poses if sonar is not None else np.zeros((0, 3))
        self._sonar_poses = poses
        self._cone = sonar.cone if sonar is not None else 0.0
        self._camera_fov = camera_fov
        self._sighting: tuple[float, float] | None = None   # distance, bearing off the way
        self.state = GuideState()
        self.user_id: int | None = None
        self._started = 0.0
        self._seen_at: float | None = None
        self._waiting_since: float | None = None
        self._forward: float | None = None     # the way the robot leads: what "behind" means

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
        self._sighting = None
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
        self._forward = self._way(pose)
        # the nearest of the user's own track, a track behind the robot and a rear echo: the
        # own track alone once jumped onto furniture ahead (a leg-like return) while the
        # visitor stood 1.5 m behind, beside a wall, and the robot waited for the furniture
        found = [f for f in (self._own_track(pose), self._track_behind(pose),
                             self._from_sonar(pose)) if f]
        seen = min(found, key=lambda f: f[0], default=None)
        if seen is not None:
            self._seen_at = now
            self._sighting = (seen[0], seen[1] + pose.th - self._way_or_heading(pose))
        else:
            seen = self._remembered(pose, now)
        if seen is not None:
            distance, bearing, xy, source = seen
            unseen = 0.0 if source != "memory" else now - self._seen_at
            self.state = replace(self.state, user_distance=distance, user_bearing=bearing,
                                 user_xy=xy, source=source, unseen_for=unseen)
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

    def _remembered(self, pose, now: float):
        """The follower's last sighting, for up to BLIND_MEMORY s, while the place it puts
        them (as far behind, as far off the way) is where none of the robot's sensors looks,
        or behind a wall of the map: ARGOS, with no sonar behind, turned round, saw its
        visitor and turned back to the way, lost them at once and stopped again after a few
        decimetres; at a corner the simulated visitor stops 1.5 m away on the far side of the
        corner's wall, where nothing sees them, and HOROS waited 30 s for them (generated
        building 2, tour 12). Never refreshed by itself, and never where a sonar, the laser or
        the camera could see the follower."""
        if self._sighting is None or self._seen_at is None or now - self._seen_at > BLIND_MEMORY:
            return None
        distance, off_way = self._sighting
        bearing = off_way + self._way_or_heading(pose) - pose.th
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        x = pose.x + distance * math.cos(pose.th + bearing)
        y = pose.y + distance * math.sin(pose.th + bearing)
        if self._watched(bearing) and self._in_sight(x, y, pose):
            return None
        return distance, bearing, (x, y), "memory"

    def _watched(self, bearing: float) -> bool:
        """Whether a sensor of the robot looks at `bearing` (robot frame): a sonar's cone,
        the laser's scan, the camera's field (as if looking ahead)."""
        if len(self._sonar_poses):
            off = self._sonar_poses[:, 2] - bearing
            if (np.abs(np.arctan2(np.sin(off), np.cos(off))) <= self._cone / 2).any():
                return True
        scan = getattr(self.perception, "scan", None)
        if scan is not None and len(scan.angles):
            a = bearing - scan.origin[2]
            a = math.atan2(math.sin(a), math.cos(a))
            if scan.angles[0] <= a <= scan.angles[-1]:
                return True
        return abs(bearing) <= self._camera_fov / 2

    def _own_track(self, pose):
        """The guided user's own track, while the tracker still has it."""
        own = next((t for t in self.perception.tracks if t.id == self.user_id), None)
        if own is None or not self._in_sight(own.x, own.y, pose):
            return None
        return _seen(own, pose)

    def _track_behind(self, pose):
        """The nearest confirmed track behind the robot within reach (in any direction near
        the goal). Not in any direction while the robot waits: ARGOS, which cannot see behind
        it, took someone standing 3.2 m ahead for its visitor and never turned round to look
        (the guide's group_blocking scenario)."""
        nav = self.blackboard.value("navigation/state")
        anywhere = (nav is not None and nav.distance_left <= NEAR_GOAL)
        behind = [t for t in self.perception.tracks
                  if (anywhere or abs(self._off_way(t.x, t.y, pose)) > BEHIND)
                  and math.hypot(t.x - pose.x, t.y - pose.y) <= self.reach
                  and self._in_sight(t.x, t.y, pose)]
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
        lx, ly = p[:, 0] + r * np.cos(p[:, 2]), p[:, 1] + r * np.sin(p[:, 2])
        open_ = ~self._walls_explain(pose, r, p, self._cone_rays(lx, ly, pose.w))
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

    def _cone_rays(self, lx: np.ndarray, ly: np.ndarray, turn_rate: float) -> np.ndarray:
        """Per echo (at lx, ly in the robot frame), the directions off its sonar's axis (rad)
        that the map checks: across the whole cone where the laser looks (it finds a person
        there, so the sonar must be sure), across the part where a sonar hears walls (±cone/3)
        elsewhere; widened by the turn the robot makes in SONAR_AGE, since an echo may be that
        old (ARGOS, turning round at 90°/s to look, took a wall heard 9° further round for a
        visitor)."""
        half = np.full(len(lx), self._cone * HEARD)
        scan = getattr(self.perception, "scan", None)
        if scan is not None and len(scan.angles):
            ox, oy, oh = scan.origin
            a = np.arctan2(ly - oy, lx - ox) - oh
            a = np.arctan2(np.sin(a), np.cos(a))
            half[(a >= scan.angles[0]) & (a <= scan.angles[-1])] = self._cone / 2
        turned = abs(turn_rate) * SONAR_AGE
        spread = np.linspace(-1.0, 1.0, 5 if turned == 0.0 else 9)
        return (half + turned)[:, None] * spread[None, :]

    def _walls_explain(self, pose, r: np.ndarray, p: np.ndarray, rays: np.ndarray
                       ) -> np.ndarray:
        """Per echo (range r of the sonar at pose p, robot frame): a ray of `rays` (rad off
        the sonar's axis) meets a wall of the map before the echo's range, or at most WALL_SLACK beyond
        it (a sonar hears the nearest thing in its cone)."""
        c, s = math.cos(pose.th), math.sin(pose.th)
        steps = np.arange(0.0, float(r.max()) + WALL_SLACK + 1e-9, MARCH_STEP)
        t = np.minimum(steps[None, :], (r + WALL_SLACK)[:, None])          # n × samples
        explained = np.zeros(len(r), dtype=bool)
        for k in range(rays.shape[1]):
            a = p[:, 2] + rays[:, k]
            lx = p[:, 0, None] + t * np.cos(a)[:, None]
            ly = p[:, 1, None] + t * np.sin(a)[:, None]
            wx, wy = pose.x + c * lx - s * ly, pose.y + s * lx + c * ly
            explained |= (self.grid.clearance(wx, wy) <= WALL_HIT).any(axis=1)
        return explained

    def _in_sight(self, x: float, y: float, pose) -> bool:
        """No wall of the map between the robot and (x, y): a track through a wall is a ghost."""
        if self.grid is None:
            return True
        n = max(2, int(math.hypot(x - pose.x, y - pose.y) / MARCH_STEP))
        f = np.linspace(0.0, 1.0, n)
        return bool((self.grid.clearance(pose.x + f * (x - pose.x),
                                         pose.y + f * (y - pose.y)) > WALL_HIT / 2).all())

    def _way(self, pose) -> float | None:
        """The direction the robot leads in: from it towards the path `AHEAD` m on from the
        point of the navigation's path nearest to it (a robot turned round to look still knows
        its way); without a path, the last one known."""
        path = self.blackboard.value("navigation/path")
        if not path or len(path) < 2:
            return self._forward
        points = np.asarray(path, dtype=float)
        a, b = points[:-1], points[1:]
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", (pose.x, pose.y) - a, ab)
                    / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12), 0.0, 1.0)
        nearest = a + t[:, None] * ab
        i = int(np.argmin(np.hypot(nearest[:, 0] - pose.x, nearest[:, 1] - pose.y)))
        ahead = np.vstack([nearest[i], points[i + 1:]])
        steps = np.hypot(*np.diff(ahead, axis=0).T)
        along = np.concatenate([[0.0], np.cumsum(steps)])
        j = int(np.searchsorted(along, AHEAD))
        if j >= len(ahead):
            target = ahead[-1]
        else:
            f = (AHEAD - along[j - 1]) / max(steps[j - 1], 1e-12)
            target = ahead[j - 1] + f * (ahead[j] - ahead[j - 1])
        if math.hypot(target[0] - pose.x, target[1] - pose.y) < 0.1 or along[-1] < 0.1:
            # on the goal, or past it (come in fast): the way it came; towards the goal from
            # beyond it is backwards, and the rear sonars took the visitor for ahead
            return self._forward
        return math.atan2(target[1] - pose.y, target[0] - pose.x)

    def _way_or_heading(self, pose) -> float:
        return pose.th if self._forward is None else self._forward

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
