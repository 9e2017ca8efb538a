"""The local controller: a dynamic window approach that follows the global path around what the
map does not know — range readings and people walking.

Each tick it samples commands (v, w) reachable within one tick under the profile's acceleration
limits, simulates each over a short horizon (the body ramps to the command at its acceleration
limit, then holds it), drops every command whose trajectory would bring the body within
`safety_margin` of the map's walls, of a range reading, or of a person (people move on at their
tracked velocity; a walking person counts only while the robot is still moving: passive safety,
so the robot may always stand still rather than freeze with no command), and scores the rest
(personal-space intrusion over a longer `people_horizon`, so it steps aside early): progress along the path, heading along it, stay
near the path, keep clear of walls, keep out of people's personal space, go fast. Near people the
speed is capped at the profile's `max_speed_near_people`, and the robot slows to stop on the goal
and before anything that blocks its path (then it reports itself blocked, with the blocker).

The body is the robot's footprint (`footprint.Footprint`): a circle, or a rectangle checked
along its outline; people keep their distance from its circumscribed circle. Where the path
ahead leaves less than OPEN either side, the speed is capped: `narrow_speed` for an opening a
little wider than the robot (TIGHT either side), more in a wider one, there only as early as
braking needs; closeness the path itself needs (less than CLEAR) costs nothing.

Commands are forward only (v >= 0): the robots' sensors look ahead; turning on the spot is
always among the samples. The controller is stateless: the skill passes the remaining path.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy.spatial import cKDTree

from robots.profile import Limits
from skills.fastclip import clip as _clip
from skills.navigation.costmap import CostMap
from skills.navigation.footprint import Footprint
from skills.safety import LEFT_BEHIND

PERSON_RADIUS = 0.25       # m: a person's body as an obstacle (shoulders, arms)
MOVING = 0.4               # m/s: slower counts as standing (tracking noise): static, may block
CLEAR = 0.12               # m of free space (beyond body and margin) below which closeness costs
TIGHT = 0.09               # m either side (beyond body and margin) at which openings are passed at
                           # narrow_speed: doors 0.25 m wider than the robot leave 0.05-0.07 m
OPEN = 0.11                # m either side from which the path's openings cost no speed (a 1 m
                           # hallway leaves PERSES 0.10-0.115 m, HOROS 0.2 m)
NARROW_EARLY = 0.3         # m before a wider opening the robot is down to its speed there
STOPPED = 0.02             # m/s: the robot counts as standing still (passive safety)
UNMAPPED = 0.15            # m: a reading this far from any mapped wall is a new obstacle


@dataclass(frozen=True)
class ControllerParams:
    tick: float = 0.1              # s between commands
    horizon: float = 2.0           # s simulated ahead
    step: float = 0.1              # s between simulated poses
    v_samples: int = 7
    w_samples: int = 15
    lookahead: float = 1.0         # m down the path to the point steered at
    safety_margin: float = 0.04    # m kept free around the body along every trajectory
    personal_space: float = 0.6    # m beyond body contact that people should be left
    people_anticipation: float = 1.0   # s: slow down this long before coming near a person
    people_horizon: float = 4.0    # s over which personal-space intrusion is scored (not vetoed)
    block_margin: float = 0.10     # m: an obstacle this close to the path's swept body blocks it
    block_lookahead: float = 2.0   # m of path checked for obstructions
    standoff: float = 0.35         # m the robot stops (centre, along the path) before an obstruction
    resume_margin: float = 0.15    # m more the way must open before a robot held up creeps on (the
                                   # blocker's estimate jitters by centimetres: stop-and-creep
                                   # would split one wait into many)
    rotate_first: float = math.radians(70)   # heading error beyond which it turns on the spot
    brake: float = 0.8             # fraction of max_accel planned for stopping (goal, obstruction)
    # closeness to walls costs only where the body comes closer than the planned path itself
    # does within the next metres: counting the closeness a door a little wider than the robot
    # forces made standing before it the best command (issue 22)
    clearance_beyond_path: bool = True
    narrow_speed: float = 0.25     # m/s through openings that leave TIGHT either side (up to full
                                   # speed at OPEN)
    narrow_lookahead: float = 1.0  # m of path ahead checked for such an opening
    w_progress: float = 1.0
    w_heading: float = 0.6
    w_path: float = 0.8
    w_clearance: float = 1.2
    w_people: float = 3.0
    w_speed: float = 0.4


@dataclass(frozen=True)
class Person:
    """A person as the controller sees them: position and velocity in the map frame."""
    x: float
    y: float
    vx: float = 0.0
    vy: float = 0.0


@dataclass(frozen=True)
class Command:
    """What the controller chose and why."""
    v: float
    w: float
    admissible: bool = True          # a collision-free command was found
    blocked: bool = False            # stopped before an obstruction, or no admissible command
    blocker: tuple[float, float] | None = None   # where the way is blocked (map frame)
    reason: str = ""
    speed_cap: float = math.inf      # m/s the command was capped to (people, goal, obstruction)
    trajectory: np.ndarray | None = None        # (k, 3) predicted poses of the command


class LocalController:
    def __init__(self, costmap: CostMap, limits: Limits,
                 params: ControllerParams = ControllerParams(),
                 footprint: Footprint | None = None) -> None:
        self.costmap = costmap
        self.limits = limits
        self.params = params
        # the body checked against walls and readings; people keep their distance from its
        # circumscribed circle
        self.footprint = footprint or Footprint.round(costmap.radius)
        self.radius = self.footprint.circumscribed
        self._half_width = (self.footprint.width / 2 if not self.footprint.is_round
                            else self.footprint.radius)
        # distance field values are between cell centres: a wall may be up to this much closer
        self._cell_slack = costmap.grid.resolution * math.sqrt(0.5)
        self._times = np.arange(1, int(round(params.horizon / params.step)) + 1) * params.step
        braking = limits.max_speed ** 2 / (2 * params.brake * limits.max_accel)
        # m of path any piece looks at (`_PathAhead`)
        self._farthest = max(params.narrow_lookahead + braking, params.block_lookahead,
                             limits.max_speed * params.horizon + params.lookahead,
                             limits.max_speed * params.people_horizon)
        self._corners_of: CostMap | None = None      # the cost map of _corner_table
        self._corner_table = np.zeros((0, 5))
        self._long_times = np.arange(1, int(round(max(params.people_horizon, params.horizon)
                                                 / params.step)) + 1) * params.step

    # -- the tick --------------------------------------------------------------------------

    def step(self, pose, velocity, path, *, points=None, people: Sequence = (),
             max_speed: float | None = None, block_points=None, held: bool = False,
             lead_off: bool = False) -> Command:
        """The command for this tick. `pose` (x, y, th) and `velocity` (v, w) of the robot;
        `path` (n, 2) the rest of the global path from the robot's projection to the goal;
        `points` (k, 2) range readings in the map frame; `people` with x, y, vx, vy;
        `block_points` the readings precise enough to say the path is blocked (default:
        `points`; wide sonar cones place an echo too loosely for that); `held` while the
        caller counts the robot as held up by an obstruction (it then stands `resume_margin`
        further back before it moves towards the obstruction again); `lead_off` scores the
        heading halfway through the horizon as well (a guide leading a visitor off)."""
        p = self.params
        x, y, th = (float(v) for v in pose)
        v0, w0 = (float(v) for v in velocity)
        path = np.asarray(path, dtype=float).reshape(-1, 2)
        # the path's segment and arc lengths, once a tick for every resampling of it
        arc = _arc(path)
        points = np.zeros((0, 2)) if points is None else np.asarray(points, float).reshape(-1, 2)
        crowd = _people_array(people)
        reach = self.limits.max_speed * p.horizon + self.radius + 1.0
        near = _within(points, x, y, reach)
        block_near = near if block_points is None else _within(
            np.asarray(block_points, float).reshape(-1, 2), x, y, reach)

        stretch = _PathAhead(self, path, arc)
        cap, cap_why = self._speed_cap(x, y, th, v0, path, crowd, max_speed, arc, stretch)
        block_at, blocker = self._obstruction(path, block_near, crowd, arc, stretch)
        if block_at is not None:
            room = max(0.0, block_at - p.standoff - (p.resume_margin if held else 0.0))
            stop_cap = math.sqrt(2 * p.brake * self.limits.max_accel * room) if room > 0.05 else 0.0
            if stop_cap < cap:
                cap, cap_why = stop_cap, "obstruction"
        target = (_point_along(path, p.lookahead, arc) if len(path)
                  else np.array([x, y]))
        bearing = math.atan2(target[1] - y, target[0] - x)
        turning = (abs(_wrap(bearing - th)) > p.rotate_first
                   and math.hypot(target[0] - x, target[1] - y) > 0.05)
        if turning:
            cap, cap_why = min(cap, 0.0), cap_why or "turning"

        vs, ws = self._sample_speeds(v0, w0, cap)
        commands = np.column_stack([np.repeat(vs, len(ws)), np.tile(ws, len(vs))])
        # the longer people horizon only with people to score (its first poses are the
        # horizon's: the same cumulative sums), and their distances once for both uses
        long_poses = _rollout_grid(x, y, th, v0, w0, vs, ws,
                                   self._long_times if len(crowd) else self._times, self.limits)
        poses = long_poses[:, : len(self._times)]
        people_d = (self._people_distance(long_poses, crowd, self._long_times) if len(crowd)
                    else None)
        speeds = np.repeat(_speeds(v0, vs[:, None], self._times, self.limits), len(ws), axis=0)
        gap, gap0 = self._gaps(x, y, th, v0, poses, speeds, near, crowd, people_d)
        unsafe = (gap < 0.0) & (gap < gap0[:, None] - 1e-9)
        ok = ~unsafe.any(axis=1)
        if not ok.any():
            return Command(0.0, 0.0, admissible=False, blocked=True,
                           blocker=blocker or _nearest(x, y, near, crowd), speed_cap=cap,
                           reason="no collision-free command within the horizon")
        score = self._score(commands, poses, people_d, gap, gap0, crowd, path, target, cap,
                            turning, lead_off, arc, stretch)
        score[~ok] = np.inf
        best = int(np.argmin(score))
        v, w = (float(c) for c in commands[best])
        blocked = block_at is not None and v < 0.02 and v0 < 0.05     # held up before it
        reason = (f"way blocked {block_at:.2f} m ahead along the path" if blocked else cap_why)
        return Command(v, w, True, blocked, blocker if blocked else None, reason, cap, poses[best])

    # -- pieces ----------------------------------------------------------------------------

    def _speed_cap(self, x, y, th, v0, path, crowd, max_speed, arc=None,
                   stretch=None) -> tuple[float, str]:
        """The speed limit of this tick: profile, caller, people near, the goal ahead (`arc`:
        the path's `_arc`, and `stretch` its `_PathAhead`, when known)."""
        limits, p = self.limits, self.params
        cap, why = limits.max_speed, ""
        if max_speed is not None and max_speed < cap:
            cap, why = max(0.0, float(max_speed)), "requested speed"
        if len(crowd):
            crowd = crowd[_not_left_behind(crowd, x, y, th, v0, p.people_anticipation)]
        if len(crowd):
            ahead_x = x + v0 * p.people_anticipation * math.cos(th)
            ahead_y = y + v0 * p.people_anticipation * math.sin(th)
            later = crowd[:, :2] + crowd[:, 2:] * p.people_anticipation
            now_d = np.hypot(crowd[:, 0] - x, crowd[:, 1] - y)
            later_d = np.hypot(later[:, 0] - ahead_x, later[:, 1] - ahead_y)
            if min(now_d.min(), later_d.min()) < limits.near_people_distance:
                if limits.max_speed_near_people < cap:
                    cap, why = limits.max_speed_near_people, "people near"
        # the path starts at the robot's projection onto it: a robot beside the goal (come
        # in fast, off to one side) has no path left but still its distance to go
        left = _length(path, arc)
        if len(path):
            left = max(left, math.hypot(path[-1][0] - x, path[-1][1] - y))
        goal_cap = math.sqrt(2 * p.brake * limits.max_accel * left)
        if goal_cap < cap:
            cap, why = goal_cap, "goal ahead"
        if p.narrow_speed < cap and len(path) >= 2:
            narrow_cap = self._narrow_cap(path, arc, stretch)
            if narrow_cap < cap:
                cap, why = narrow_cap, "narrow passage"
        return cap, why

    def _narrow_cap(self, path, arc=None, stretch=None) -> float:
        """The speed cap of the openings on the path ahead. Near an opening that leaves no
        more than TIGHT either side (a door 0.25 m wider than the robot) anything under CLEAR
        within `narrow_lookahead` caps at `narrow_speed`, as it always did; elsewhere an
        opening under OPEN caps at a speed rising linearly from `narrow_speed` at TIGHT to full
        speed at OPEN, from NARROW_EARLY before it, and before that at what still brakes to it.
        The flat cap for everything under CLEAR made PERSES crawl at 0.25 m/s along whole 1 m
        hallways (0.10-0.11 m either side): 45 of 132 s guiding in a generated building (issue
        22, point 6). Tight doors keep it: HOROS in a 0.65 m door creeps past jambs the safety
        arbiter sees 2-8 cm ahead, and any faster approach there stalled it as "blocked"."""
        p, limits = self.params, self.limits
        braking = limits.max_speed ** 2 / (2 * p.brake * limits.max_accel)
        stretch = stretch or _PathAhead(self, path, arc)
        _, along = stretch.window(p.narrow_lookahead + braking)
        gaps = stretch.gaps(p.narrow_lookahead + braking)
        if gaps.min() <= TIGHT:         # the old rule, the same approach and speed
            near = along <= p.narrow_lookahead
            return p.narrow_speed if gaps[near].min() < CLEAR else limits.max_speed
        share = _clip((gaps - TIGHT) / (OPEN - TIGHT), 0.0, 1.0)
        allowed = p.narrow_speed + share * (limits.max_speed - p.narrow_speed)
        room = np.maximum(along - NARROW_EARLY, 0.0)
        reach = np.sqrt(allowed ** 2 + 2 * p.brake * limits.max_accel * room)
        return float(reach.min())

    def _obstruction(self, path, points, crowd, arc=None, stretch=None):
        """(metres along the path, (x, y)) of the first obstruction within block_lookahead.

        Obstructions are readings off the map's walls and people standing, not people walking
        (the trajectories avoid those; the way clears as they walk on)."""
        p = self.params
        if len(path) < 2:
            return None, None
        blockers = np.zeros((0, 2))
        if len(points):
            off_map = self.costmap.grid.clearance(points[:, 0], points[:, 1]) > UNMAPPED
            candidates = points[off_map]
            walking = crowd[np.hypot(crowd[:, 2], crowd[:, 3]) >= MOVING] if len(crowd) else crowd
            if len(walking) and len(candidates):
                d = np.hypot(candidates[:, None, 0] - walking[None, :, 0],
                             candidates[:, None, 1] - walking[None, :, 1])
                candidates = candidates[d.min(axis=1) > 0.6]
            blockers = candidates
        limit = np.full(len(blockers), self._half_width + p.block_margin)
        if len(crowd):
            standing = crowd[np.hypot(crowd[:, 2], crowd[:, 3]) < MOVING]
            blockers = np.vstack([blockers, standing[:, :2]])
            limit = np.concatenate([limit, np.full(len(standing), self._half_width
                                                   + PERSON_RADIUS + p.block_margin)])
        if not len(blockers):
            return None, None
        samples, along = (stretch or _PathAhead(self, path, arc)).window(p.block_lookahead)
        d = np.hypot(samples[:, None, 0] - blockers[None, :, 0],
                     samples[:, None, 1] - blockers[None, :, 1])
        hit = d < limit[None, :]
        rows = np.flatnonzero(hit.any(axis=1))
        if not len(rows):
            return None, None
        first = rows[0]
        which = int(np.argmin(np.where(hit[first], d[first], np.inf)))
        return float(along[first]), (float(blockers[which, 0]), float(blockers[which, 1]))

    def _sample_speeds(self, v0, w0, cap) -> tuple[np.ndarray, np.ndarray]:
        """The speeds and turn rates whose every pair is a command sampled: reachable in one
        tick, within the caps, plus stopping and turning (np.linspace's and np.unique's
        values, in plain floats: these few dozen numbers cost more in numpy calls)."""
        limits, p = self.limits, self.params
        dv, dw = limits.max_accel * p.tick, limits.max_turn_accel * p.tick
        v_hi = min(cap, v0 + dv, limits.max_speed)
        v_lo = min(max(0.0, v0 - dv), v_hi)
        vs = sorted(set(_linspace(v_lo, v_hi, p.v_samples) + [0.0]))
        w_lo = max(-limits.max_turn_rate, w0 - dw)
        w_hi = min(limits.max_turn_rate, w0 + dw)
        if w_lo > w_hi:                     # spinning faster than allowed: slow the turn
            w_lo = w_hi = math.copysign(limits.max_turn_rate, w0)
        ws = _linspace(w_lo, w_hi, p.w_samples)
        if w_lo < 0.0 < w_hi:
            ws = sorted(set(ws + [0.0]))
        return np.array(vs, dtype=float), np.array(ws, dtype=float)

    def _gaps(self, x, y, th, v0, poses, speeds, points, crowd, people_d=None):
        """Free space (m) beyond body + margin at every pose (s, k), and at the start (s,)
        (`people_d`: the people's `_people_distance` over the long horizon, when known).

        A walking person counts only where the robot is still moving then (passive safety):
        standing still is always allowed, else a person walking at a stopped robot would leave
        it no command at all, and it would freeze in their way instead of stepping aside."""
        p = self.params
        px, py, pth = poses[..., 0], poses[..., 1], poses[..., 2]
        here = (np.array([x]), np.array([y]), np.array([th]))
        gap = self._wall_gap(px, py, pth)
        gap0 = float(self._wall_gap(*here)[0])
        if len(points):
            # one k-d tree of the readings for the poses and the start
            tree = cKDTree(points) if self._tree_needed(len(points)) else None
            gap = np.minimum(gap, self._points_gap(px, py, pth, points, tree))
            gap0 = min(gap0, float(self._points_gap(*here, points, tree)[0]))
        if len(crowd):
            d = (self._people_distance(poses, crowd, self._times) if people_d is None
                 else people_d[:, : poses.shape[1]])
            walking = np.hypot(crowd[:, 2], crowd[:, 3]) > 0.0
            # the robot counts as moving at a pose when it moved at any time since the previous
            # one: it may stop between two poses, and a walker reaching it before it has stopped
            # would fall through a check at the poses alone (speed ramps are monotonic)
            before = np.concatenate([np.full((len(speeds), 1), v0), speeds[:, :-1]], axis=1)
            still = np.maximum(before, speeds) <= STOPPED
            d = np.where(walking[None, None, :] & still[..., None], np.inf, d)
            gap = np.minimum(gap, d.min(axis=-1) - self.radius - PERSON_RADIUS)
            gap0 = min(gap0, float(np.hypot(crowd[:, 0] - x, crowd[:, 1] - y).min())
                       - self.radius - PERSON_RADIUS)
        gap = gap - p.safety_margin
        return gap, np.full(poses.shape[0], gap0 - p.safety_margin)

    def _intrusion(self, people_d, crowd, path, arc=None, stretch=None) -> np.ndarray:
        """(s,) worst intrusion (0 … 1) into a person's personal space over `people_horizon`.

        For a person standing, only the intrusion beyond what the path itself needs counts: the
        planner already passes them as widely as the map allows, and a squeeze it cannot avoid
        must not make standing still the best command (the robot would never pass)."""
        p = self.params
        reach = self.radius + PERSON_RADIUS + p.personal_space
        d = people_d.min(axis=1)     # (s, m): the `_people_distance` over people_horizon
        intrusion = _clip((reach - d) / p.personal_space, 0.0, 1.0)
        standing = np.hypot(crowd[:, 2], crowd[:, 3]) == 0.0
        if standing.any() and len(path) >= 2:
            window, _ = (stretch or _PathAhead(self, path, arc)).window(
                self.limits.max_speed * p.people_horizon)
            on_path = np.hypot(window[:, None, 0] - crowd[None, standing, 0],
                               window[:, None, 1] - crowd[None, standing, 1]).min(axis=0)
            needed = _clip((reach - on_path) / p.personal_space, 0.0, 1.0)
            intrusion[:, standing] = np.maximum(intrusion[:, standing] - needed[None, :], 0.0)
        return intrusion.max(axis=1)

    def _run_on(self, path: np.ndarray, length: float) -> np.ndarray:
        """The path with a straight piece of up to `length` m past its end, along its last
        direction, as far as the body (its circumscribed circle) stays off the map's walls."""
        if len(path) < 2:
            return path
        step = path[-1] - path[-2]
        norm = float(np.hypot(*step))
        if norm < 1e-9:
            return path
        along = np.arange(0.05, length + 1e-9, 0.05)
        piece = path[-1] + (step / norm)[None, :] * along[:, None]
        free = self._map_clearance(piece[:, 0], piece[:, 1]) - self._cell_slack > self.radius
        n = len(free) if free.all() else int(np.argmin(free))
        return path if n == 0 else np.vstack([path, piece[n - 1]])

    def _path_gaps(self, window: np.ndarray) -> np.ndarray:
        """The free space (beyond body and margin, walls of the map only) at each point of
        this stretch of the planned path, the body turned along it."""
        if len(window) < 2:
            return np.full(max(len(window), 1), CLEAR)
        step = np.diff(window, axis=0)
        heading = np.arctan2(step[:, 1], step[:, 0])
        heading = np.concatenate([heading, heading[-1:]])
        return self._wall_gap(window[:, 0], window[:, 1], heading) - self.params.safety_margin

    def _wall_gap(self, px, py, pth) -> np.ndarray:
        """Gap between the footprint at poses (any shape) and the map's walls. A rectangle's
        outline is checked where its circumscribed circle comes near a wall."""
        centre = self._map_clearance(px, py) - self._cell_slack
        if self.footprint.is_round:
            return centre - self.radius
        gap = centre - self.radius
        near = gap < CLEAR + self.params.safety_margin
        if near.any():
            ox, oy = self.footprint.outline_at(px[near], py[near], pth[near])
            gap[near] = self._map_clearance(ox, oy).min(axis=-1) - self._cell_slack
        return gap

    def _points_gap(self, px, py, pth, points: np.ndarray, tree=None) -> np.ndarray:
        """Gap between the footprint at poses (any shape) and the nearest range reading
        (`tree`: a k-d tree of `points`, made here when needed and not given)."""
        if self.footprint.is_round:
            return _nearest_distance(px, py, points, tree) - self.radius
        if len(points) <= NEAREST_READINGS:
            # the tree would preselect them all (the same readings, another order): the gap is
            # their least, in any order
            return self.footprint.gap_to_points(px, py, pth, points)
        tree = tree if tree is not None else cKDTree(points)
        # the readings nearest the centre: the one nearest the outline is among them for any
        # reading the outline comes near (a scan's neighbouring beams are close together)
        k = min(NEAREST_READINGS, len(points))
        _, index = tree.query(np.column_stack([px.ravel(), py.ravel()]), k=k)
        index = index.reshape(px.shape + (k,))
        return self.footprint.gap_to_points(px, py, pth, points[index])

    def _tree_needed(self, readings: int) -> bool:
        """Whether `_points_gap` queries a k-d tree of this many readings."""
        return readings > (SQUARES_UP_TO if self.footprint.is_round else NEAREST_READINGS)

    def _map_clearance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Distance to the walls, interpolated between cell centres (0 off the map): smooth,
        so a move of a centimetre never looks like a step towards a wall."""
        grid = self.costmap.grid
        x, y = np.asarray(x, float), np.asarray(y, float)
        if x.size == 1 and x.shape == y.shape:      # the robot's own pose, once a tick
            at = self._point_clearance(float(x.flat[0]), float(y.flat[0]))
            if at is not None:
                return np.full(x.shape, at)
        if x.ndim == 0 and y.ndim == 0:
            return self._map_clearance(x[None], y[None]).reshape(())
        fx = (x - grid.origin[0]) / grid.resolution - 0.5
        fy = (y - grid.origin[1]) / grid.resolution - 0.5
        floor_x, floor_y = np.floor(fx), np.floor(fy)
        c0, r0 = floor_x.astype(int), floor_y.astype(int)
        tx, ty = fx - floor_x, fy - floor_y          # fx - c0: the int converts back exactly
        rows, cols = self.costmap.clearance.shape
        # the cell's corners by flat index (np.clip and 2-D fancy indexing cost more than the
        # arithmetic on the few hundred poses of a tick); a corner left unclamped is on the map
        r, c = np.minimum(np.maximum(r0, 0), rows - 2), np.minimum(np.maximum(c0, 0), cols - 2)
        inside = (r == r0) & (c == c0)
        corners = np.take(self._corners(), r * cols + c, axis=0)
        f00, f01, f10, f11, lowest = (corners[..., k] for k in range(5))
        # in place: the same products and sums, in the same order, as (1 - tx) * (1 - ty) *
        # f00 + tx * (1 - ty) * f01 + (1 - tx) * ty * f10 + tx * ty * f11
        ux, uy = 1 - tx, 1 - ty
        d = ux * uy
        d *= f00
        term = tx * uy
        term *= f01
        d += term
        np.multiply(ux, ty, out=term)
        term *= f10
        d += term
        np.multiply(tx, ty, out=term)
        term *= f11
        d += term
        np.minimum(d, lowest, out=d)
        return d if inside.all() else np.where(inside, d, 0.0)

    def _point_clearance(self, x: float, y: float) -> float | None:
        """`_map_clearance` of one point in plain floats: the same cell, the same products
        and sums in the same order, np.minimum's rule (a NaN wins) for the cap; None for a
        point whose cell a float cannot name (left to the arrays). A dozen array calls cost
        more than the arithmetic of one point."""
        grid = self.costmap.grid
        fx = (x - grid.origin[0]) / grid.resolution - 0.5
        fy = (y - grid.origin[1]) / grid.resolution - 0.5
        if not (math.isfinite(fx) and math.isfinite(fy)):
            return None
        c0, r0 = math.floor(fx), math.floor(fy)
        tx, ty = fx - c0, fy - r0
        rows, cols = self.costmap.clearance.shape
        r, c = min(max(r0, 0), rows - 2), min(max(c0, 0), cols - 2)
        if r != r0 or c != c0:
            return 0.0
        f00, f01, f10, f11, lowest = self._corners()[r * cols + c].tolist()
        ux, uy = 1 - tx, 1 - ty
        d = ux * uy * f00 + tx * uy * f01 + ux * ty * f10 + tx * ty * f11
        return d if (d <= lowest or d != d) else lowest

    def _corners(self) -> np.ndarray:
        """(cells, 5) for the square of cell centres whose lower left corner is each cell:
        the field at its four corners (f00, f01, f10, f11) and the least of them plus a cell,
        which caps the interpolated distance; one gather per pose instead of four and their
        minima. Made once per cost map."""
        if self._corners_of is self.costmap:
            return self._corner_table
        field = self.costmap.clearance
        rows, cols = field.shape
        flat = field.ravel()
        at = np.arange((rows - 2) * cols + cols - 1)
        f00, f01, f10, f11 = flat[at], flat[at + 1], flat[at + cols], flat[at + (cols + 1)]
        lowest = np.minimum(np.minimum(f00, f01), np.minimum(f10, f11)) + \
            self.costmap.grid.resolution
        self._corner_table = np.column_stack([f00, f01, f10, f11, lowest])
        self._corners_of = self.costmap
        return self._corner_table

    def _people_distance(self, poses, crowd, times) -> np.ndarray:
        """(s, k, m) distance from each pose to each person where they will be then."""
        t = times[None, :, None]
        fx = crowd[None, None, :, 0] + crowd[None, None, :, 2] * t
        fy = crowd[None, None, :, 1] + crowd[None, None, :, 3] * t
        return np.hypot(poses[..., 0, None] - fx, poses[..., 1, None] - fy)

    def _score(self, commands, poses, people_d, gap, gap0, crowd, path, target,
               cap, turning: bool = False, lead_off: bool = False, arc=None,
               stretch=None) -> np.ndarray:
        """Lower is better: progress along the path, heading along it, distance from it,
        clearance, people's personal space, speed."""
        p = self.params
        stretch = stretch or _PathAhead(self, path, arc)
        end = poses[:, -1, :]
        if len(path) >= 2:
            reach = self.limits.max_speed * p.horizon + p.lookahead
            needed = (float(stretch.gaps(reach).min()) if p.clearance_beyond_path
                      else CLEAR)
            # scored against the path run on straight past the goal (as far as the body fits):
            # a command held for the whole horizon overshoots a goal that the goal cap will
            # stop it at, and scored as leaving the path, made the robot crawl the last metre
            # (0.26 m/s down to 0.09)
            if stretch.length > reach + 1e-9:       # every sample on the path itself
                window, _ = stretch.window(reach)
            else:
                window, _ = _resample(self._run_on(path, reach), 0.05, reach)
            every_other = poses[:, 1::2, :2]
            at, off = _project(every_other.reshape(-1, 2), window)
            if poses.shape[1] % 2 == 0:     # the last pose is among them: projected already
                along = at.reshape(len(poses), -1)[:, -1]
            else:
                along, _ = _project(end[:, :2], window)
            off_path = off.reshape(len(poses), -1).max(axis=1)
            ahead = np.minimum(along + p.lookahead / 2, 0.05 * (len(window) - 1))
            index = np.rint(ahead / 0.05).astype(int)
            aim = window[index]
            progress = (self.limits.max_speed * p.horizon - along) / max(
                self.limits.max_speed * p.horizon, 1e-3)
        else:
            aim = np.broadcast_to(target, end[:, :2].shape)
            off_path = np.hypot(target[0] - end[:, 0], target[1] - end[:, 1])
            progress = np.zeros(len(end))
            needed = CLEAR
        to_aim = np.hypot(aim[:, 0] - end[:, 0], aim[:, 1] - end[:, 1])
        heading = np.abs(_wrap(np.arctan2(aim[:, 1] - end[:, 1], aim[:, 0] - end[:, 0])
                               - end[:, 2])) / math.pi
        heading = np.where(to_aim < 0.1, 0.0, heading)
        if lead_off:
            # and halfway: scored at the horizon's end alone, a turn that lines up just then
            # (0.5 rad/s for 1 rad) scored as well as a quick one, and a guide led off slowly.
            # Only for a guide: a follower scored so followed a look-alike crossing close past
            # its customer out of the store (tests/skills/test_following.py, HOROS)
            mid = poses[:, len(self._times) // 2 - 1, :]
            to_mid = np.abs(_wrap(np.arctan2(aim[:, 1] - mid[:, 1], aim[:, 0] - mid[:, 0])
                                  - mid[:, 2])) / math.pi
            heading = 0.5 * (heading + np.where(to_aim < 0.1, 0.0, to_mid))
        # only getting closer to walls and readings costs: standing near one is no reason to
        # stay; with clearance_beyond_path, only closer than the path itself goes (a door a
        # little wider than the robot needs less than CLEAR: counting that made standing
        # before it the best command)
        floor = min(CLEAR, needed)
        closer = _clip((floor - gap.min(axis=1)) / CLEAR, 0.0, 1.0)
        clearance = np.maximum(closer - _clip((floor - gap0) / CLEAR, 0.0, 1.0), 0.0)
        if turning:
            # turning on the spot to face the way: a rectangle's corners sweep nearer a wall
            # and back, which must not make standing still best (the safety check stays)
            clearance = np.zeros(len(commands))
        intrusion = 0.0
        if len(crowd):
            intrusion = self._intrusion(people_d, crowd, path, arc, stretch)
        top = max(cap, 1e-3)
        speed = _clip((top - commands[:, 0]) / top, 0.0, 1.0)
        return (p.w_progress * progress + p.w_heading * heading
                + p.w_path * np.minimum(off_path, 1.0) + p.w_clearance * clearance
                + p.w_people * intrusion + p.w_speed * speed)


class _PathAhead:
    """The path ahead resampled every 5 cm once a tick, up to the farthest any piece of the
    controller looks (the goal and narrow caps, the obstruction check, the score, the
    people's intrusion), and the body's room along it. A shorter stretch is its first samples:
    np.arange's values are i * 0.05 whatever the stop, and np.interp's each point's own."""

    def __init__(self, controller: "LocalController", path: np.ndarray, arc=None) -> None:
        self.controller = controller
        self.path = path
        self.arc = arc or _arc(path)
        self.length = float(self.arc[1][-1])        # m along the path
        self._samples = self._along = self._gaps = None

    def window(self, limit: float) -> tuple[np.ndarray, np.ndarray]:
        """`_resample(path, 0.05, limit)`: (samples, arc lengths)."""
        if self._samples is None:
            self._samples, self._along = _resample(self.path, 0.05, self.controller._farthest,
                                                   self.arc)
        count = len(np.arange(0.0, min(limit, self.length) + 1e-9, 0.05))
        return self._samples[:count], self._along[:count]

    def gaps(self, limit: float) -> np.ndarray:
        """`_path_gaps` of `window(limit)`: the room at each sample, computed once. A
        rectangle faces along the path, and at a stretch's last sample along its last step."""
        window, _ = self.window(limit)
        controller = self.controller
        if len(window) < 2:
            return controller._path_gaps(window)
        if self._gaps is None:
            self._gaps = controller._path_gaps(self._samples)
        count = len(window)
        if count == len(self._samples) or controller.footprint.is_round:
            return self._gaps[:count]
        last = controller._path_gaps(window[-2:])[-1]
        return np.concatenate([self._gaps[: count - 1], [last]])


def _speeds(v0: float, commands: np.ndarray, times: np.ndarray, limits: Limits) -> np.ndarray:
    """(s, k) forward speed at the sample times: ramping from v0 to each command."""
    dv = commands[:, 0:1] - v0
    return v0 + _clip(dv, -limits.max_accel * times, limits.max_accel * times)


def _linspace(start: float, stop: float, num: int) -> list[float]:
    """np.linspace(start, stop, num) (num >= 2) as a list of floats, computed as numpy does:
    i * step + start, the last exactly `stop` (i / div * delta + start for a zero step)."""
    div = num - 1
    delta = stop - start
    step = delta / div
    if step == 0:
        values = [i / div * delta + start for i in range(num)]
    else:
        values = [i * step + start for i in range(num)]
    values[-1] = stop
    return values


def _rollout_grid(x, y, th, v0, w0, vs: np.ndarray, ws: np.ndarray, times: np.ndarray,
                  limits: Limits) -> np.ndarray:
    """The poses at `times` of every speed in `vs` with every turn rate in `ws` (the commands of
    `_samples`, speed-major): the same poses, with each speed's and each turn rate's ramp,
    headings and their cosines and sines computed once for all the commands sharing it."""
    edges = np.concatenate([[0.0], times])
    mids = 0.5 * (edges[1:] + edges[:-1])
    dts = np.diff(edges)
    v = v0 + _clip(vs[:, None] - v0, -limits.max_accel * mids, limits.max_accel * mids)
    w = w0 + _clip(ws[:, None] - w0, -limits.max_turn_accel * mids,
                   limits.max_turn_accel * mids)
    dth = w * dts
    th_end = th + np.cumsum(dth, axis=1)
    th_mid = th_end - 0.5 * dth
    step = (v * dts)[:, None, :]                 # (speeds, 1, k) against (turn rates, k)
    poses = np.empty((len(vs), len(ws), len(times), 3))
    np.cumsum(step * np.cos(th_mid), axis=2, out=poses[..., 0])
    poses[..., 0] += x
    np.cumsum(step * np.sin(th_mid), axis=2, out=poses[..., 1])
    poses[..., 1] += y
    poses[..., 2] = th_end
    return poses.reshape(len(vs) * len(ws), len(times), 3)


def _nearest_distance(px: np.ndarray, py: np.ndarray, points: np.ndarray,
                      tree=None) -> np.ndarray:
    """Distance from every pose (px, py of one shape) to its nearest point (k, 2): np.hypot up
    to KD_TREE_FROM points, beyond that the k-d tree's distances (`tree`, or without one up to
    SQUARES_UP_TO points, `_least_square_distance`). Every sampled pose against every reading
    in one array was the controller's largest cost with a laser scan of a crowd around."""
    if len(points) <= KD_TREE_FROM:
        if not len(points) or np.size(px) <= FEW_POSES:
            return np.hypot(px[..., None] - points[:, 0],
                            py[..., None] - points[:, 1]).min(axis=-1)
        # one reading at a time: the same distances and minima as the (poses, readings)
        # array's, without it and its reduction over a short last axis
        dx, dy = np.empty_like(px, dtype=float), np.empty_like(py, dtype=float)
        nearest = None
        for rx, ry in points.tolist():
            np.subtract(px, rx, out=dx)
            np.subtract(py, ry, out=dy)
            if nearest is None:
                nearest = np.hypot(dx, dy)
            else:
                np.minimum(nearest, np.hypot(dx, dy, out=dx), out=nearest)
        return nearest
    if tree is None and len(points) <= SQUARES_UP_TO:
        return np.sqrt(_least_square_distance(px, py, points))
    tree = tree if tree is not None else cKDTree(points)
    distance, _ = tree.query(np.column_stack([px.ravel(), py.ravel()]))
    return distance.reshape(px.shape)


def _least_square_distance(px: np.ndarray, py: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The least dx * dx + dy * dy from every pose to the points, summed as scipy's k-d tree
    sums them (its query returns the square root of the nearest's), one point at a time: the
    same distances as the tree's, without its ~0.3 µs per pose (~0.8 ms a tick for the
    controller's few thousand poses)."""
    if np.size(px) <= FEW_POSES:          # (poses, points) arrays: fewer calls
        dx = px[..., None] - points[:, 0]
        dy = py[..., None] - points[:, 1]
        return (dx * dx + dy * dy).min(axis=-1)
    least = dx = dy = None
    for rx, ry in points.tolist():
        dx = np.subtract(px, rx, out=dx)
        dx *= dx
        dy = np.subtract(py, ry, out=dy)
        dy *= dy
        dx += dy
        if least is None:
            least, dx = dx, None
        else:
            np.minimum(least, dx, out=least)
    return least


KD_TREE_FROM = 8     # points: below, the plain distances are as fast
SQUARES_UP_TO = 64   # points: up to here, the k-d tree's distances without the tree
FEW_POSES = 16       # poses: up to here, distances to points in one (poses, points) array
NEAREST_READINGS = 16   # readings per pose checked against a rectangle's outline


def _not_left_behind(crowd: np.ndarray, x: float, y: float, th: float, v0: float,
                     anticipation: float) -> np.ndarray:
    """(m,) True for the people the near-people cap is for: all but those more than
    LEFT_BEHIND off the robot's heading now and `anticipation` s on (both moving as now). The
    controller drives forward only, so it can only leave those farther behind; slowing down
    would let them close in. The guided visitor following at 1-1.5 m capped a guide at 0.3 m/s
    long after it had passed them (issue 22, point 6)."""
    later = crowd[:, :2] + crowd[:, 2:] * anticipation
    ahead_x = x + v0 * anticipation * math.cos(th)
    ahead_y = y + v0 * anticipation * math.sin(th)
    now = np.abs(_wrap(np.arctan2(crowd[:, 1] - y, crowd[:, 0] - x) - th))
    then = np.abs(_wrap(np.arctan2(later[:, 1] - ahead_y, later[:, 0] - ahead_x) - th))
    return (now <= LEFT_BEHIND) | (then <= LEFT_BEHIND)


def _people_array(people) -> np.ndarray:
    """(m, 4) x, y, vx, vy; a person slower than MOVING stands still (tracking noise)."""
    if not people:
        return np.zeros((0, 4))
    crowd = np.array([[float(q.x), float(q.y), float(q.vx), float(q.vy)] for q in people])
    crowd[np.hypot(crowd[:, 2], crowd[:, 3]) < MOVING, 2:] = 0.0
    return crowd


def _nearest(x: float, y: float, points: np.ndarray, crowd: np.ndarray):
    """The nearest reading or person, as (x, y); None when there is neither."""
    candidates = np.vstack([points.reshape(-1, 2), crowd[:, :2].reshape(-1, 2)])
    if not len(candidates):
        return None
    i = int(np.argmin(np.hypot(candidates[:, 0] - x, candidates[:, 1] - y)))
    return float(candidates[i, 0]), float(candidates[i, 1])


def _within(points: np.ndarray, x: float, y: float, reach: float) -> np.ndarray:
    if not len(points):
        return points
    return points[np.hypot(points[:, 0] - x, points[:, 1] - y) <= reach]


def _wrap(angle):
    return np.arctan2(np.sin(angle), np.cos(angle))


def _arc(path: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(segment lengths, arc length at each vertex) of a path."""
    seg = np.hypot(*np.diff(path, axis=0).T)
    return seg, np.concatenate([[0.0], np.cumsum(seg)])


def _length(path: np.ndarray, arc=None) -> float:
    if len(path) < 2:
        return 0.0
    seg = (arc or _arc(path))[0]
    return float(seg.sum())


def _resample(path: np.ndarray, spacing: float, limit: float,
              arc=None) -> tuple[np.ndarray, np.ndarray]:
    """Points every `spacing` m along the path up to `limit` m, and their arc lengths
    (`arc`: the path's `_arc`, when known)."""
    _, cum = arc or _arc(path)
    along = np.arange(0.0, min(limit, cum[-1]) + 1e-9, spacing)
    xs = np.interp(along, cum, path[:, 0])
    ys = np.interp(along, cum, path[:, 1])
    return np.column_stack([xs, ys]), along


def _point_along(path: np.ndarray, distance: float, arc=None) -> np.ndarray:
    """The point `distance` m along the path (its end if shorter)."""
    if len(path) < 2:
        return path[-1]
    _, cum = arc or _arc(path)
    d = min(distance, cum[-1])
    return np.array([np.interp(d, cum, path[:, 0]), np.interp(d, cum, path[:, 1])])


def _project(points: np.ndarray, samples: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(arc length, distance) of each point's nearest sample of a path resampled every 5 cm."""
    px, py = points[:, 0], points[:, 1]
    square = np.subtract.outer(px, samples[:, 0])     # in place: the same products and sum
    square *= square                                  # as dx * dx + dy * dy, fewer arrays
    dy = np.subtract.outer(py, samples[:, 1])
    dy *= dy
    square += dy
    nearest = square.argmin(axis=1)                   # squares order them as distances do
    return nearest * 0.05, np.hypot(px - samples[nearest, 0], py - samples[nearest, 1])
