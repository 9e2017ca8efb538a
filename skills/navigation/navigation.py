"""The navigation skill: drive to a place of the map or a pose, around people and obstacles.

`go_to` plans a global path on the inflated cost map; every tick the local controller turns the
rest of the path, the range readings and the tracked people into a velocity. The skill never
talks to the base: it owns the motion goal "navigate", and `Motion.act` asks it for the
velocity and sends that through the safety arbiter, which keeps the last word.

Its typed status, for a state graph:
- running (reason '' while driving; 'paused'; 'blocked for N s …' while the way is blocked);
- succeeded ('arrived at …');
- failed with a reason that starts with one of NO_PATH, BLOCKED, LOCALIZATION_LOST,
  UNKNOWN_PLACE, so a graph can branch on it.
`navigation/state` carries the same as values (phase, blocked_for, distance_left, goal, …).

When the way stays blocked it waits `replan_after` seconds, then plans again with what blocks
it drawn into the map; without another way it waits on and gives up after `give_up_after`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
from scipy.spatial import cKDTree

from robots.profile import RobotProfile
from skills.localization import Localization
from skills.obstacles import explained_echoes
from skills.motion import Goal, Motion
from skills.navigation.controller import (ControllerParams, LocalController, Person,
                                          PERSON_RADIUS, MOVING)
from skills.navigation.costmap import CostMap, robot_cost_map
from skills.navigation.footprint import Footprint, inside
from skills.navigation.gridmap import GridMap, MapError
from skills.navigation.planner import GlobalPlanner, Plan
from skills.perception import PeoplePerception
from skills.safety import STOP_DISTANCE
from skills.skill import Skill
from skills.status import IDLE, SkillStatus, Status, failed

# phases (NavigationState.phase)
IDLE_PHASE = "idle"
DRIVING = "driving"
TURNING = "turning"          # on the goal, turning to its heading
PAUSED = "paused"
BLOCKED = "blocked"
ARRIVED = "arrived"
FAILED = "failed"

# failure codes: the first words of a failed status's reason (and NavigationState.failure)
NO_PATH = "no path"
BLOCKED_GAVE_UP = "blocked"
LOCALIZATION_LOST = "localization lost"
UNKNOWN_PLACE = "unknown place"

TURN_GAIN = 1.5              # rad/s per rad of heading error on the goal
OFF_PATH = 1.0               # m from the path at which the robot plans again from where it is
READING_SIZE = 0.25          # m drawn around an off-map reading when planning around it
SONAR_RANGE = 1.5            # m: farther sonar echoes are too wide to steer by
IGNORED_RADIUS = 0.45        # m around an ignored person whose readings do not block
ON_MAP = 0.09                # m: a reading this near a mapped wall (cell centre) is that wall
EXCUSE = "Excuse me, may I pass, please?"   # the words a robot asks `person_blocking` with
PERSON_AT_BLOCKER = 0.6     # m: a track this near what blocks the way is a person in it
IN_A_WALL = 0.15             # m: a "person" closer than this to a wall is a door jamb's echo
CONFIRM_RADIUS = 0.05        # m: a laser reading counts when the previous scan had one this near


@dataclass(frozen=True)
class NavigationParams:
    goal_tolerance: float = 0.15          # m from the goal counted as there
    # m from the goal counted as there when the safety arbiter will not let the robot closer
    # (a place drawn near a wall, approached facing the wall)
    wall_goal_tolerance: float = 0.3
    heading_tolerance: float = math.radians(8)
    replan_after: float = 3.0             # s blocked before planning around the obstruction
    give_up_after: float = 30.0           # s blocked before failing
    clear_after: float = 1.0              # s the way must be clear to end a blocked episode
    stuck_after: float = 10.0             # s without 0.2 m of progress counted as blocked
    lost_grace: float = 1.0               # s of lost localization tolerated (standing still)
    controller: ControllerParams = field(default_factory=ControllerParams)


@dataclass(frozen=True)
class NavigationState:
    """What the skill is doing, as values (`navigation/state`)."""
    phase: str = IDLE_PHASE
    goal: str = ""                        # place name, or "(x, y)" for a pose
    target: tuple[float, float, float | None] | None = None   # x, y m; heading rad or None
    distance_left: float = math.inf       # m along the path
    blocked_for: float = 0.0              # s the way has been blocked (0 when not)
    blocker: tuple[float, float] | None = None
    replans: int = 0
    speed: float | None = None            # m/s requested cap (None: the profile's)
    failure: str = ""                     # one of the failure codes when phase is failed
    reason: str = ""


class Navigation(Skill):
    name = "navigation"

    def __init__(self, blackboard, events, grid: GridMap, profile: RobotProfile,
                 localization: Localization, perception: PeoplePerception, motion: Motion,
                 laser=None, params: NavigationParams = NavigationParams()) -> None:
        super().__init__(blackboard, events)
        self.grid = grid
        self.profile = profile
        self.limits = profile.limits
        self.localization = localization
        self.perception = perception
        self.motion = motion
        self.laser = laser
        self.params = params
        sonar = profile.sonar
        self._sonar_poses = sonar.poses if sonar is not None else np.zeros((0, 3))
        self.state = NavigationState()
        self.plan: Plan | None = None
        self.points = np.zeros((0, 2))         # range readings this tick, map frame
        self.block_points = np.zeros((0, 2))
        self.last_command = None
        self._target: tuple[float, float, float | None] | None = None
        self._speed: float | None = None
        self._lead = False          # go_to(lead=True): a guide's goal
        self._segment = 0
        self._blocked_since: float | None = None
        self._clear_since: float | None = None
        self._attempts = 0
        self._found_way = False                  # the last plan-around attempt found a way
        self._progress: tuple[float, float] | None = None    # (distance left, time) of progress
        self._last_replan = -math.inf
        self._lost_since: float | None = None
        # tracks the controller does not treat as people to keep away from and slow down for
        # (the customer a follower drives behind; their legs still count as readings)
        self.ignore_people: frozenset[int] = frozenset()
        self._previous_scan: np.ndarray | None = None    # laser readings of the last tick, map frame
        motion.navigator = self

    @cached_property
    def footprint(self) -> Footprint:
        return Footprint.of(self.profile)

    @cached_property
    def costmap(self) -> CostMap:
        """Made on the first goal (cached per map), so opening a robot stays cheap."""
        return robot_cost_map(self.grid, self.footprint, self.params.controller.safety_margin)

    @cached_property
    def planner(self) -> GlobalPlanner:
        return GlobalPlanner(self.costmap)

    @cached_property
    def controller(self) -> LocalController:
        return LocalController(self.costmap, self.limits, self.params.controller,
                               self.footprint)

    # -- the API for behaviors -------------------------------------------------------------

    @property
    def places(self) -> list[str]:
        return sorted(self.grid.places)

    def go_to(self, target, now: float, *, speed: float | None = None,
              lead: bool = False) -> SkillStatus:
        """Drive to a place name of the map or a pose (x, y[, heading rad]) at up to `speed`
        m/s (None: the profile's max_speed); replaces any current goal. `lead`: a guide
        leading someone, who turns onto the way sooner (the controller's `lead_off`). Returns
        the status: running, or failed at once for an unknown place, a bad pose or no path."""
        self._lead = lead
        if speed is not None:
            self.set_speed(speed)
        else:
            self._speed = None
        self._reset()
        try:
            name, goal = self._resolve(target)
        except (MapError, ValueError) as exc:
            self.state = NavigationState(goal=str(target))
            code = UNKNOWN_PLACE if isinstance(exc, MapError) else NO_PATH
            return self._fail(code, str(exc), now)
        self._target = goal
        self.state = NavigationState(DRIVING, name, goal, speed=self._speed)
        self.motion.start(Goal("navigate"), now)
        self.set_status(SkillStatus(Status.RUNNING), now)
        if self.localization.state is not None:
            self._make_plan(now)
        self._publish(now)
        return self.status

    def set_speed(self, max_speed: float | None) -> None:
        """Cap the driving speed (a guide's pace), m/s; None returns to the profile's limit."""
        if max_speed is not None:
            top = self.limits.max_speed
            if not (isinstance(max_speed, (int, float)) and math.isfinite(max_speed)
                    and 0.0 < max_speed <= top):
                raise ValueError(f"navigation speed {max_speed!r} m/s is outside 0 < speed <= "
                                 f"{top} (the profile's max_speed)")
            max_speed = float(max_speed)
        self._speed = max_speed
        if self.state.phase not in (IDLE_PHASE, ARRIVED, FAILED):
            self.state = _replace(self.state, speed=max_speed)

    def pause(self, now: float) -> None:
        """Stand still and keep the goal; `resume` drives on."""
        if self.state.phase in (DRIVING, TURNING, BLOCKED):
            self._blocked_since = None
            self._set_phase(PAUSED, now, SkillStatus(Status.RUNNING, "paused"))

    def resume(self, now: float) -> None:
        """Drive on after `pause` (or after another motion goal took the base)."""
        if self.state.phase == PAUSED:
            self._progress = None
            self.motion.start(Goal("navigate"), now)
            self._set_phase(DRIVING, now, SkillStatus(Status.RUNNING))

    def cancel(self, now: float) -> None:
        """Drop the goal and stand still."""
        self._release(now)
        self._reset()
        self.state = NavigationState()
        self.set_status(IDLE, now)
        self.write("navigation/path", (), now)
        self._publish(now)

    def person_blocking(self, near: float = PERSON_AT_BLOCKER, ignore=frozenset()):
        """The person standing in the way while the way is blocked: a track within `near` m
        of what blocks it, ahead of the robot and off the walls (a door jamb's echo the leg
        detector took for legs is no one to ask), not one of `ignore` (track ids); else
        None. Who to ask to let the robot pass."""
        blocker = self.state.blocker if self.state.phase == BLOCKED else None
        pose = self.localization.state
        if blocker is None or pose is None:
            return None
        ahead = (math.cos(pose.th), math.sin(pose.th))
        for track in self.perception.tracks:
            if (track.id not in ignore
                    and math.hypot(track.x - blocker[0], track.y - blocker[1]) <= near
                    and (track.x - pose.x) * ahead[0] + (track.y - pose.y) * ahead[1] > 0
                    and self.grid.clearance_at(track.x, track.y) > IN_A_WALL):
                return track
        return None

    # -- the tick --------------------------------------------------------------------------

    def sense(self, now: float) -> None:
        """With a goal: collect the range readings in the map frame; notice another motion goal
        taking the base."""
        state = self.localization.state
        if state is None or self.state.phase not in (DRIVING, TURNING, BLOCKED, PAUSED):
            return
        self.points, self.block_points = self._readings(state)
        if self.ignore_people:
            self.points = self._without_ignored(self.points)
            self.block_points = self._without_ignored(self.block_points)
        if self.state.phase in (DRIVING, TURNING, BLOCKED):
            goal = self.motion.goal
            if goal is None or goal.kind != "navigate":
                kind = goal.kind if goal is not None else "none"
                self._set_phase(PAUSED, now, SkillStatus(
                    Status.RUNNING, f"paused: motion goal '{kind}' took the base; resume() "
                    "to drive on"))

    def velocity(self, now: float) -> tuple[float, float]:
        """The velocity of the "navigate" motion goal (called by Motion.act every tick)."""
        if self.state.phase not in (DRIVING, TURNING, BLOCKED):
            return 0.0, 0.0
        state = self.localization.state
        if state is None:
            return 0.0, 0.0
        if self._lost(now):
            return 0.0, 0.0
        if self.plan is None and not self._make_plan(now):
            return 0.0, 0.0
        x, y, th = state.x, state.y, state.th
        tx, ty, heading = self._target
        to_goal = math.hypot(tx - x, ty - y)
        if (self.state.phase == TURNING or to_goal <= self.params.goal_tolerance
                or (to_goal <= self.params.wall_goal_tolerance and self._wall_ahead())):
            return self._turn_on_goal(heading, th, state.w, now)
        rest = self._rest_of_path(x, y)
        if math.hypot(rest[0, 0] - x, rest[0, 1] - y) > OFF_PATH:
            if not self._make_plan(now):        # pushed off the path, or a jump of the estimate
                return 0.0, 0.0
            rest = self._rest_of_path(x, y)
        people = [Person(t.x, t.y, t.vx, t.vy) for t in self.perception.tracks
                  if t.id not in self.ignore_people]
        command = self.controller.step((x, y, th), (state.v, state.w), rest,
                                       points=self._unmapped(self.points), people=people,
                                       max_speed=self._speed, block_points=self.block_points,
                                       held=self._blocked_since is not None,
                                       lead_off=self._lead)
        if (not command.admissible and self._blocked_since is None
                and (self.last_command is None or self.last_command.admissible)):
            # one tick without a safe move stops the robot for that tick; a blocked way is one
            # that stays so (a stray return of the laser beside the body is gone a tick later)
            command = replace(command, blocked=False)
        self.last_command = command
        left = _length(rest)
        if command.blocked:
            self._progress = None       # waiting before a blocker is not a lack of progress
        elif self._stuck(left, now):
            command = replace(command, blocked=True, reason=f"no progress for "
                              f"{self.params.stuck_after:.0f} s")
        if command.blocked:
            self._clear_since = None
            self._on_blocked(command, now, left)
        elif self._still_blocked(now):
            self._on_blocked(command, now, left)
        else:
            self._blocked_since = None
            self.state = _replace(self.state, phase=DRIVING, distance_left=left, blocked_for=0.0,
                                  blocker=None, reason=command.reason)
            self.set_status(SkillStatus(Status.RUNNING), now)
        self._publish(now)
        if self.state.phase == FAILED:
            return 0.0, 0.0
        return command.v, command.w

    # -- pieces ----------------------------------------------------------------------------

    def _resolve(self, target) -> tuple[str, tuple[float, float, float | None]]:
        if isinstance(target, str):
            x, y, heading = self.grid.place(target)
            return target, (x, y, heading)
        try:
            values = [float(v) for v in target]
        except (TypeError, ValueError):
            raise ValueError(f"navigation target {target!r} must be a place name or (x, y[, "
                             f"heading]); places: {', '.join(self.places)}") from None
        if len(values) not in (2, 3) or not all(math.isfinite(v) for v in values):
            raise ValueError(f"navigation target {target!r} must be (x, y) or (x, y, heading) "
                             "in metres and radians, all finite")
        heading = values[2] if len(values) == 3 else None
        return f"({values[0]:.2f}, {values[1]:.2f})", (values[0], values[1], heading)

    def _make_plan(self, now: float, costmap=None) -> bool:
        state = self.localization.state
        plan = self.planner.plan((state.x, state.y), self._target[:2], costmap)
        if not plan.found:
            if costmap is None:
                self._fail(NO_PATH, plan.reason, now)
            return False
        self.plan = plan
        self._segment = 0
        self.write("navigation/path", tuple((float(px), float(py)) for px, py in plan.waypoints),
                   now)
        return True

    def _on_blocked(self, command, now: float, left: float) -> None:
        p = self.params
        if self._blocked_since is None:
            self._blocked_since = now
        blocked_for = now - self._blocked_since
        where = command.blocker or self.state.blocker
        at = f" at ({where[0]:.2f}, {where[1]:.2f})" if where is not None else ""
        if blocked_for >= p.give_up_after:
            tries = f"{self._attempts} tries to plan around it"
            why = (f"though a way around was planned ({tries})" if self._found_way
                   else f"and there is no other way ({tries})")
            self._fail(BLOCKED_GAVE_UP, f"the way{at} stayed blocked for {blocked_for:.0f} s "
                       f"{why}", now)
            return
        replans = self.state.replans
        note = ""
        if blocked_for >= p.replan_after and now - self._last_replan >= p.replan_after:
            self._last_replan = now
            self._attempts += 1
            if self._replan_around(now):
                replans += 1
                note = "; re-planned around it"
            else:
                note = "; no other way, waiting"
        self.state = _replace(self.state, phase=BLOCKED, distance_left=left,
                              blocked_for=blocked_for, blocker=where, replans=replans,
                              reason=command.reason + note)
        self.set_status(SkillStatus(Status.RUNNING, f"blocked for {int(blocked_for)} s{at}"), now)

    def _wall_ahead(self) -> bool:
        """The safety arbiter stops forward motion here (too little free space ahead), so
        creeping on to the goal would stand still until the skill gives up."""
        return self.blackboard.value("obstacles/front", math.inf) < STOP_DISTANCE + 0.02

    def _stuck(self, left: float, now: float) -> bool:
        """No 0.2 m of progress along the path for `stuck_after` seconds (a local minimum of
        the controller, or something it cannot see as blocking): handled as blocked."""
        mark = self._progress
        if mark is None or left < mark[0] - 0.2:
            self._progress = (left, now)
            return False
        return now - mark[1] >= self.params.stuck_after

    def _still_blocked(self, now: float) -> bool:
        """A blocked episode ends only after the way has been clear for `clear_after` seconds
        (a blocker seen on and off is one episode, not many short ones)."""
        if self._blocked_since is None:
            return False
        if self._clear_since is None:
            self._clear_since = now
        if now - self._clear_since < self.params.clear_after:
            return True
        self._blocked_since = self._clear_since = None
        return False

    def _replan_around(self, now: float) -> bool:
        """Plan again with the readings off the map and the people standing as obstacles."""
        state = self.localization.state
        points = self.block_points
        if len(points):
            off_map = self.grid.clearance(points[:, 0], points[:, 1]) > 0.15
            near = np.hypot(points[:, 0] - state.x, points[:, 1] - state.y) < 4.0
            points = points[off_map & near]
        standing = np.array([(t.x, t.y) for t in self.perception.tracks
                             if math.hypot(t.vx, t.vy) < MOVING]).reshape(-1, 2)
        # people drawn wider than the controller's blocking distance, so the new path is clear
        person = PERSON_RADIUS + self.params.controller.block_margin + 0.05
        sizes = np.concatenate([np.full(len(points), READING_SIZE), np.full(len(standing), person)])
        costmap = self.costmap.with_obstacles(np.vstack([points.reshape(-1, 2), standing]), sizes)
        found = self._make_plan(now, costmap)
        self._found_way = found
        return found

    def _turn_on_goal(self, heading, th, w0, now: float) -> tuple[float, float]:
        """On the goal: turn to its heading (if any), then arrive."""
        p = self.params
        error = 0.0 if heading is None else math.atan2(math.sin(heading - th),
                                                       math.cos(heading - th))
        if abs(error) < p.heading_tolerance:
            self._arrive(now)
            return 0.0, 0.0
        self.state = _replace(self.state, phase=TURNING, distance_left=0.0, blocked_for=0.0)
        self.set_status(SkillStatus(Status.RUNNING), now)
        self._publish(now)
        return 0.0, self._goal_turn_rate(error, w0)

    def _goal_turn_rate(self, error: float, w0: float) -> float:
        """The turn rate towards the goal's heading: as fast as still stops (at a share
        `controller.brake` of the turn acceleration) within the heading tolerance, and at
        least the proportional TURN_GAIN rate. The proportional rate alone crept through the
        last 30 degrees: turning on the goal took 1.7 s of a guide tour for 100 degrees."""
        p, limits = self.params, self.limits
        step = limits.max_turn_accel * p.controller.tick
        left = max(abs(error) - p.heading_tolerance / 2, 0.0)
        stopping = math.sqrt(2 * p.controller.brake * limits.max_turn_accel * left)
        w = math.copysign(min(limits.max_turn_rate, max(stopping, TURN_GAIN * abs(error))), error)
        return max(w0 - step, min(w0 + step, w))

    def _arrive(self, now: float) -> None:
        self._release(now)
        self.state = _replace(self.state, phase=ARRIVED, distance_left=0.0, blocked_for=0.0,
                              blocker=None, reason="")
        self.set_status(SkillStatus(Status.SUCCEEDED, f"arrived at {self.state.goal}"), now)
        self._publish(now)

    def _fail(self, code: str, detail: str, now: float) -> SkillStatus:
        self._release(now)
        reason = f"{code}: {detail}"
        self.state = _replace(self.state, phase=FAILED, failure=code, reason=reason)
        self.set_status(failed(reason), now)
        self._publish(now)
        return self.status

    def _lost(self, now: float) -> bool:
        """No trustworthy pose (the localization says it is lost, or the base state is stale):
        stand still; fail after `lost_grace` seconds (no driving on by itself after a fault)."""
        why = ""
        if getattr(self.localization, "lost", False):
            why = "the pose estimate is lost"
        elif not self.blackboard.value("robot/link", False):
            why = f"the base state is stale or its link is down ({self.localization.status})"
        if not why:
            self._lost_since = None
            return False
        if self._lost_since is None:
            self._lost_since = now
        if now - self._lost_since >= self.params.lost_grace:
            self._fail(LOCALIZATION_LOST, f"{why}, for {now - self._lost_since:.1f} s; stopped",
                       now)
        return True

    def _rest_of_path(self, x: float, y: float) -> np.ndarray:
        """The path from the robot's projection on it to the goal (segments never go back).
        In plain floats (a few numbers a tick): np.dot's two products and sum, np.clip's
        clamp (`_unit`)."""
        points = self.plan.waypoints
        first = self._segment
        near = points[first: first + 4].tolist()
        best, best_d, best_p = first, math.inf, near[0]
        for k in range(len(near) - 1):
            (ax, ay), (bx, by) = near[k], near[k + 1]
            abx, aby = bx - ax, by - ay
            t = _unit(((x - ax) * abx + (y - ay) * aby) / max(abx * abx + aby * aby, 1e-12))
            qx, qy = ax + t * abx, ay + t * aby
            d = math.hypot(x - qx, y - qy)
            if d < best_d - 1e-9:
                best, best_d, best_p = first + k, d, (qx, qy)
        self._segment = best
        return np.vstack([best_p, points[best + 1:]])

    def _readings(self, state) -> tuple[np.ndarray, np.ndarray]:
        """Laser and near sonar end points in the map frame; those precise enough to block."""
        c, s = math.cos(state.th), math.sin(state.th)
        local = []
        laser_points = np.zeros((0, 2))
        if self.laser is not None:
            scan = self.laser.read()
            if scan is not None:
                hit = np.isfinite(scan.ranges)
                r, a = scan.ranges[hit], scan.angles[hit]     # robot frame: mount included
                laser_points = np.column_stack([scan.origin[0] + r * np.cos(a),
                                                scan.origin[1] + r * np.sin(a)])
                laser_points = laser_points[~inside(self.footprint, laser_points)]
                local.append(laser_points)
        sonar_points = np.zeros((0, 2))
        if len(state.sonar) and len(self._sonar_poses):
            ranges = np.asarray(state.sonar, dtype=float)[: len(self._sonar_poses)]
            poses = self._sonar_poses[: len(ranges)]
            # an echo the laser explains is where the laser sees it (on the cone's axis, a
            # door's jamb would stand before a robot passing the door)
            explained = explained_echoes(ranges, poses, self.profile.sonar.cone, laser_points)
            echo = np.isfinite(ranges) & (ranges <= SONAR_RANGE) & ~explained
            r, poses = ranges[echo], poses[echo]
            sonar_points = np.column_stack([poses[:, 0] + r * np.cos(poses[:, 2]),
                                            poses[:, 1] + r * np.sin(poses[:, 2])])
            local.append(sonar_points)
        if not local:
            return np.zeros((0, 2)), np.zeros((0, 2))

        def to_map(pts: np.ndarray) -> np.ndarray:
            return np.column_stack([state.x + c * pts[:, 0] - s * pts[:, 1],
                                    state.y + s * pts[:, 0] + c * pts[:, 1]])
        laser_map = self._confirmed(to_map(laser_points))
        everything = np.vstack([laser_map, to_map(sonar_points)])
        precise = laser_map if self.laser is not None else to_map(sonar_points)
        return everything, precise

    def _unmapped(self, points: np.ndarray) -> np.ndarray:
        """The readings the map's walls do not already account for: a reading on a mapped
        wall (within ON_MAP of it) says nothing the controller's distance to the walls does
        not, while its range noise (a few cm) ate the little room a narrow door leaves. With
        the pose off by more than that, the readings are off the walls and count again."""
        if not len(points):
            return points
        return points[self.grid.clearance(points[:, 0], points[:, 1]) > ON_MAP]

    def _confirmed(self, points: np.ndarray) -> np.ndarray:
        """The laser readings (map frame) that the previous scan confirms: one of its readings
        within CONFIRM_RADIUS. A real scanner returns now and then a beam short of what it hit
        (dust, an edge, a mixed pixel); such a stray reading, alone in one scan, stood in the
        way as an obstacle and could keep the way "blocked" for good. Anything really there is
        seen again a tick later (a walking person moves a few centimetres)."""
        previous, self._previous_scan = self._previous_scan, points
        if previous is None or not len(points):
            return points
        if not len(previous):
            return points[:0]
        near, _ = cKDTree(previous).query(points, distance_upper_bound=CONFIRM_RADIUS)
        return points[np.isfinite(near)]

    def _without_ignored(self, points: np.ndarray) -> np.ndarray:
        """Readings off the legs of the people in `ignore_people` are left out: a follower
        drives towards its customer at a pace that keeps its distance, which the controller,
        taking legs for fixed obstacles, would not allow. The follower stops at its minimum
        distance; the safety arbiter's stop before anything ahead stays in force."""
        keep = np.ones(len(points), dtype=bool)
        for t in self.perception.tracks:
            if t.id in self.ignore_people:
                keep &= np.hypot(points[:, 0] - t.x, points[:, 1] - t.y) > IGNORED_RADIUS
        return points[keep]

    def _set_phase(self, phase: str, now: float, status: SkillStatus) -> None:
        self.state = _replace(self.state, phase=phase, reason=status.reason)
        self.set_status(status, now)
        self._publish(now)

    def _release(self, now: float) -> None:
        """Give the base back: stop the navigate motion goal if it is still ours."""
        goal = self.motion.goal
        if goal is not None and goal.kind == "navigate":
            self.motion.cancel(now)

    def _reset(self) -> None:
        self.plan = None
        self._target = None
        self._segment = 0
        self._blocked_since = None
        self._clear_since = None
        self._attempts = 0
        self._found_way = False
        self._progress = None
        self._last_replan = -math.inf
        self._lost_since = None
        self.last_command = None
        self._previous_scan = None

    def _publish(self, now: float) -> None:
        self.write("navigation/state", self.state, now)


def _replace(state: NavigationState, **changes) -> NavigationState:
    return replace(state, **changes)


def _unit(value: float) -> float:
    """np.clip(value, 0.0, 1.0) of a float, by its rule: a NaN stays, and so does -0.0."""
    if value != value:
        return value
    value = value if value >= 0.0 else 0.0
    return value if value <= 1.0 else 1.0


def _length(path: np.ndarray) -> float:
    if len(path) < 2:
        return 0.0
    return float(np.hypot(*np.diff(path, axis=0).T).sum())
