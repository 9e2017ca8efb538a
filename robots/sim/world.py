"""The simulated world: a floor, the robot's body, scripted people, and what the robot's
sensors and devices make of them. One `numpy.random.Generator` drives every sensor's random
draw, so a run is the same for the same seed and the same sequence of calls; the wheel odometry
(`robots.sim.odometry`) and each person (a shopper's places and dwell times) draw from
generators of their own, seeded from the same seed, so what they do does not depend on how often
the robot reads its sensors. `body` is the ground truth; `odometry` is what the base reports.

The world also keeps the robot's true trail (for people who follow it) and the measures an
evaluation needs (`World.measures`, see `robots.sim.measures`).
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from robots.exceptions import FloorError, ScenarioError
from robots.profile import RobotProfile
from robots.sim.appearance import anyone, appearance_of, observed
from robots.sim.body import Obstacles, UnicycleBody
from robots.sim.outline import Rectangle
from robots.sim import heeding
from robots.sim.crowd import Crowd
from robots.sim.floor import Floor
from robots.sim.laser_errors import LaserErrors
from robots.sim.measures import NEAR_WALLS, Measures
from robots.sim.odometry import WheelOdometry, odometry_rng
from robots.sim.people import BODY_RADIUS, LEG_RADIUS, SimPerson
from robots.sim.raycast import cast_rays, point_segment_distances, segment_distances
from robots.sim.scenario import Follow, Lead, Leave, MakeWay, Scenario, Shop, Walk
from robots.sim.walkways import walk_grid

MAX_SUBSTEP = 0.05          # s
SONAR_RAY_SPREAD = (-1 / 3, 0.0, 1 / 3)   # rays across each cone, as fractions of the cone
SECONDS_PER_CHARACTER = 0.06
WALL_CACHE_MARGIN = 0.5     # m the body may move before the walls near it are chosen again
TRAIL_SPACING = 0.1         # m between the breadcrumbs of the robot's trail
STILL_SPEED = 0.02          # m/s; slower, the robot stands (turning on the spot included)
_NO_CIRCLES = np.zeros((0, 3))


@dataclass
class ScreenState:
    """What the touch screen shows and the presses not yet taken by the robot."""
    prompt: tuple[str, str, tuple[str, ...]] | None = None   # (prompt_id, text, buttons)
    shown_at: float = 0.0
    typed: bool = False                                     # the prompt takes typed text too
    info: tuple[str, str | None] | None = None             # (text, picture) without answers
    caption: str = ""                                       # what the robot says, as text
    presses: deque = field(default_factory=deque)           # of (prompt_id, button)

    def show(self, prompt_id: str, text: str, buttons: tuple[str, ...], t: float,
             typed: bool = False) -> None:
        """Show a prompt; showing the same prompt again keeps its original time."""
        prompt = (str(prompt_id), str(text), tuple(str(b) for b in buttons))
        self.info = None
        self.typed = bool(typed)
        if prompt != self.prompt:
            self.prompt = prompt
            self.shown_at = t

    def display(self, text: str, picture: str | None = None) -> None:
        self.prompt = None
        self.info = (str(text), picture)

    def clear(self) -> None:
        self.prompt = None
        self.info = None

    def press(self, prompt_id: str, button: str) -> None:
        self.presses.append((prompt_id, button))

    def take_press(self) -> tuple[str, str] | None:
        return self.presses.popleft() if self.presses else None


class World:
    """Floor, body, people and sensors, stepped together in sim time `t`."""

    def __init__(self, floor: Floor, profile: RobotProfile, scenario: Scenario | None = None,
                 seed: int = 0) -> None:
        self.floor = floor
        self.profile = profile
        self.scenario = scenario
        self.rng = np.random.default_rng(seed)
        self.appearance_rng = np.random.default_rng([seed, 0xA99])   # its own stream
        self.t = 0.0
        if scenario is not None:
            _check_floor(scenario, floor)
        x, y, th = self._start_pose()
        self.body = UnicycleBody(x, y, th, profile.limits, profile.radius,
                                 Rectangle(profile.length, profile.width)
                                 if profile.shape == "rectangle" else None)
        self.odometry = WheelOdometry((x, y, th), profile.odometry, odometry_rng(seed))
        self.people: list[SimPerson] = []
        if scenario is not None:
            _check_places(scenario, floor)
            self.people = [SimPerson(plan, self.resolve, np.random.default_rng([seed, index]))
                           for index, plan in enumerate(scenario.people)]
        self.crowd = Crowd.for_scenario(self.people, scenario, seed)   # how people move
        heeding.draw_for(self.people, scenario.heeding if scenario is not None
                         else heeding.Distribution(), seed)     # do they wait when asked
        self.appearances = {p.plan.id: appearance_of(p.plan.looks_like or p.plan.id)
                            for p in self.people}     # a look-alike dresses like another
        self.screen = ScreenState()
        self.utterances: list[tuple[float, str]] = []
        self.speaking_until = 0.0
        self.head_pan = 0.0
        self.head_tilt = 0.0
        self.hooks: list[Callable[["World", float], None]] = []
        self.trail: list[tuple[float, float]] = [(x, y)]   # the body's true path, every 0.1 m
        self.trail_lengths: list[float] = [0.0]            # m driven up to each breadcrumb
        self.measures = Measures()
        self._still_since = 0.0
        self._walls = floor.segments
        self._sonar_rays = self._sonar_ray_table()
        self._laser_offsets = self._laser_angles()
        self.laser_errors = (LaserErrors.for_floor(profile.laser, floor)
                             if profile.laser is not None else None)
        self._version = 0                  # bumped every substep; keys the caches below
        self._cache: dict[str, tuple[tuple, object]] = {}
        self._near_walls: dict[float, tuple[float, float, np.ndarray]] = {}
        self._wall_hits: dict[str, tuple[tuple[float, float, float], np.ndarray]] = {}
        self._scenes: dict[str, tuple[tuple[float, float, float], bytes, np.ndarray]] = {}

    # -- places ----------------------------------------------------------------------------

    def resolve(self, where) -> tuple[float, float]:
        """(x, y) of a place name or a point."""
        if isinstance(where, str):
            x, y, _ = self.floor.place(where)
            return x, y
        return float(where[0]), float(where[1])

    def _start_pose(self) -> tuple[float, float, float]:
        """The scenario's robot pose; without a scenario robot_home, or the origin if the
        floor has no robot_home."""
        if self.scenario is None:
            return self.floor.places.get("robot_home", (0.0, 0.0, 0.0))
        robot = self.scenario.robot
        if isinstance(robot, str):
            try:
                return self.floor.place(robot)
            except FloorError as exc:
                raise ScenarioError(f"{self.scenario.where_field('robot')}: scenario.robot: "
                                    f"{exc}") from None
        return robot

    # -- stepping --------------------------------------------------------------------------

    def step(self, dt: float) -> None:
        """Advance people and body by dt seconds in substeps of at most 0.05 s."""
        if dt <= 0:
            return
        count = max(1, math.ceil(dt / MAX_SUBSTEP - 1e-9))
        h = dt / count
        start = self.t
        for i in range(1, count + 1):
            self.t = start + h * i
            self.crowd.step(h, self)
            self._version += 1
            reach = self.body.radius + NEAR_WALLS
            walls = self._walls_near(reach)
            self.body.step(h, Obstacles(walls, self.body_circles()))
            self.odometry.step(self.body.v, self.body.w, h)
            self._version += 1
            self._record_trail()
            self.measures.update(self, h, walls)
            for hook in self.hooks:
                hook(self, h)

    def _record_trail(self) -> None:
        body = self.body
        if abs(body.v) > STILL_SPEED:
            self._still_since = self.t
        last = self.trail[-1]
        step = math.hypot(body.x - last[0], body.y - last[1])
        if step >= TRAIL_SPACING:
            self.trail.append((body.x, body.y))
            self.trail_lengths.append(self.trail_lengths[-1] + step)

    @property
    def robot_still_for(self) -> float:
        """Seconds since the robot last drove faster than 0.02 m/s (turning counts as still)."""
        return self.t - self._still_since

    def route(self, start: tuple[float, float], goal: tuple[float, float]
              ) -> list[tuple[float, float]]:
        """A person's way from start to goal around walls: the points to walk through."""
        return walk_grid(self.floor).route(start, goal)

    def walkable(self, start: tuple[float, float], goal: tuple[float, float]) -> bool:
        """True when a person walks the straight line start–goal clear of every wall."""
        return walk_grid(self.floor).clear(start, goal)

    @property
    def bumpers(self) -> int:
        return self.body.bumpers

    @property
    def stalled(self) -> bool:
        return self.body.stalled

    def say(self, text: str) -> None:
        """Record an utterance; the speaker is busy ~0.06 s per character."""
        self.utterances.append((self.t, str(text)))
        self.speaking_until = self.t + SECONDS_PER_CHARACTER * len(str(text))

    # -- what the sensors see --------------------------------------------------------------

    def present_people(self) -> list[SimPerson]:
        return [p for p in self.people if p.in_world]

    def _cached(self, key: str, compute: Callable[[], object]):
        """The value of `compute()` while nothing moved: same substep and same body pose
        (a caller may place the body by hand between steps)."""
        stamp = (self._version, self.body.x, self.body.y, self.body.th)
        hit = self._cache.get(key)
        if hit is not None and hit[0] == stamp:
            return hit[1]
        value = compute()
        self._cache[key] = (stamp, value)
        return value

    def _walls_near(self, reach: float) -> np.ndarray:
        """Walls within `reach` of the body; re-chosen only after the body moved 0.5 m."""
        body = self.body
        near = self._near_walls.get(reach)
        if near is None or math.hypot(body.x - near[0], body.y - near[1]) > WALL_CACHE_MARGIN:
            distances = point_segment_distances(body.x, body.y, self._walls)
            near = (body.x, body.y, self._walls[distances <= reach + WALL_CACHE_MARGIN])
            self._near_walls[reach] = near
        return near[2]

    def body_circles(self) -> np.ndarray:
        """People as sonar and bumpers see them: one circle each, and two per cart (k, 3)."""
        return self._cached("body_circles", self._body_circles)

    def _body_circles(self) -> np.ndarray:
        present = []
        for person in self.people:
            if person.in_world:
                present.append((person.x, person.y, BODY_RADIUS))
                present.extend(person.cart_circles())
        return np.array(present) if present else _NO_CIRCLES

    def _person_bodies(self) -> np.ndarray:
        """People alone, without carts: what hides someone from the camera (which looks over
        carts)."""
        present = [(p.x, p.y, BODY_RADIUS) for p in self.people if p.in_world]
        return np.array(present) if present else _NO_CIRCLES

    def leg_circles(self) -> np.ndarray:
        """People as the laser sees them: two leg circles each, and two per cart (2k, 3)."""
        return self._cached("leg_circles", self._leg_circles)

    def _leg_circles(self) -> np.ndarray:
        legs = []
        for person in self.people:
            if person.in_world:
                left, right = person.leg_positions()
                legs.append((left[0], left[1], LEG_RADIUS))
                legs.append((right[0], right[1], LEG_RADIUS))
                legs.extend(person.cart_circles())
        return np.array(legs) if legs else _NO_CIRCLES

    def _circles_near(self, circles: np.ndarray, reach: float) -> np.ndarray:
        """The circles whose centre is within `reach` of the body."""
        if len(circles) == 0:
            return circles
        dx = circles[:, 0] - self.body.x
        dy = circles[:, 1] - self.body.y
        return circles[dx * dx + dy * dy <= reach * reach]

    def _sonar_ray_table(self) -> np.ndarray | None:
        """Per ray (3 per sonar): x, y, heading in the robot frame."""
        sonar = self.profile.sonar
        if sonar is None:
            return None
        rays = [(x, y, h + f * sonar.cone) for x, y, h in sonar.poses for f in SONAR_RAY_SPREAD]
        return np.array(rays, dtype=float)

    def _laser_angles(self) -> np.ndarray | None:
        laser = self.profile.laser
        if laser is None:
            return None
        return laser.heading + np.linspace(-laser.fov / 2, laser.fov / 2, laser.beams)

    def _to_world(self, local: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Robot-frame (x, y, heading) rows to world-frame origins (n, 2) and angles (n,)."""
        body = self.body
        c, s = math.cos(body.th), math.sin(body.th)
        origins = np.empty((local.shape[0], 2))
        origins[:, 0] = body.x + c * local[:, 0] - s * local[:, 1]
        origins[:, 1] = body.y + s * local[:, 0] + c * local[:, 1]
        return origins, local[:, 2] + body.th

    def sonar_ranges(self) -> np.ndarray:
        """One range per sonar (m from the transducer), inf when no echo within max_range."""
        if self.profile.sonar is None:
            return np.zeros(0)
        return self._cached("sonar", self._sonar_ranges).copy()

    def _sonar_ranges(self) -> np.ndarray:
        return self._same_scene("sonar", self.body_circles(), self._sonar_cast)

    def _sonar_cast(self) -> np.ndarray:
        sonar = self.profile.sonar
        reach = sonar.max_range + float(np.hypot(*self._sonar_rays[:, :2].T).max())
        origins, angles = self._to_world(self._sonar_rays)
        circles = self._circles_near(self.body_circles(), reach + BODY_RADIUS)
        walls = self._wall_distances("sonar", origins, angles, reach)
        ranges = cast_rays(origins, angles, None, circles, sonar.max_range, walls)
        return ranges.reshape(-1, len(SONAR_RAY_SPREAD)).min(axis=1)

    def laser_scan(self, rng: np.random.Generator | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(angles in the robot frame, ranges in m from the laser) with the scanner's errors:
        Gaussian range noise, and on a map_server map drop-outs and spurious short returns.
        `rng`: another random stream for the errors (a reader that must not change the run's)."""
        laser = self.profile.laser
        if laser is None:
            return np.zeros(0), np.zeros(0)
        ranges = self._cached("laser", self._laser_ranges)
        ranges = self.laser_errors.apply(ranges, self.rng if rng is None else rng)  # sim/laser_errors.py
        return self._laser_offsets.copy(), ranges.copy()

    def _laser_ranges(self) -> np.ndarray:
        """Noise-free laser ranges of the current substep."""
        return self._same_scene("laser", self.leg_circles(), self._laser_cast)

    def _laser_cast(self) -> np.ndarray:
        laser, body = self.profile.laser, self.body
        c, s = math.cos(body.th), math.sin(body.th)
        origins = np.array([[body.x + c * laser.x - s * laser.y,
                             body.y + s * laser.x + c * laser.y]])     # one for every beam
        reach = laser.max_range + math.hypot(laser.x, laser.y)
        circles = self._circles_near(self.leg_circles(), reach + LEG_RADIUS)
        angles = self._laser_offsets + body.th
        walls = self._wall_distances("laser", origins, angles, reach)
        return cast_rays(origins, angles, None, circles, laser.max_range, walls)

    def _same_scene(self, sensor: str, circles: np.ndarray, cast: Callable[[], np.ndarray]
                    ) -> np.ndarray:
        """A sensor's noise-free ranges, cast again only when the body stands elsewhere or the
        circles it sees (people, legs, carts) differ by a bit: walls do not move, so the same
        pose and the same circles hit the same things. The survey's robot stands alone for most
        of a run, and cast the same rays every substep."""
        pose = (self.body.x, self.body.y, self.body.th)
        seen = circles.tobytes()
        kept = self._scenes.get(sensor)
        if kept is not None and kept[0] == pose and kept[1] == seen:
            return kept[2]
        ranges = cast()
        self._scenes[sensor] = (pose, seen, ranges)
        return ranges

    def _wall_distances(self, sensor: str, origins: np.ndarray, angles: np.ndarray,
                        reach: float) -> np.ndarray:
        """A sensor's rays to the walls, cast again only when the body has moved: walls do
        not move, and a robot standing still (most of a survey) would recast the same rays
        every substep."""
        pose = (self.body.x, self.body.y, self.body.th)
        kept = self._wall_hits.get(sensor)
        if kept is not None and kept[0] == pose:
            return kept[1]
        hits = segment_distances(origins, angles, self._walls_near(reach))
        self._wall_hits[sensor] = (pose, hits)
        return hits

    def detect_people(self) -> list[tuple[float, float]]:
        """Noisy person positions in the robot frame (see `person_detections`)."""
        return [(x, y) for x, y, _ in self.person_detections()]

    def person_detections(self) -> list[tuple[float, float, tuple[float, ...]]]:
        """What the camera sees: noisy person positions in the robot frame, each with its
        appearance (`robots.sim.appearance`): in range and field of view, not behind a wall or
        another person's body (the line of sight to the centre is what counts; carts are lower
        than the camera and hide nobody), each missed with `miss_rate`; plus Poisson false
        positives in the area."""
        spec = self.profile.people_detector
        if spec is None:
            return []
        body = self.body
        c, s = math.cos(body.th), math.sin(body.th)
        candidates, looks = [], []
        for person in self.people:
            if not person.in_world:
                continue
            dx, dy = person.x - body.x, person.y - body.y
            local_x, local_y = c * dx + s * dy, -s * dx + c * dy
            distance = math.hypot(local_x, local_y)
            if distance <= spec.range and abs(math.atan2(local_y, local_x)) <= spec.fov / 2:
                candidates.append((local_x, local_y, distance, math.atan2(dy, dx)))
                looks.append(self.appearances[person.plan.id])
        found = []
        if candidates:
            table = np.array(candidates)
            origins = np.array([[body.x, body.y]])                        # the camera's
            walls = cast_rays(origins, table[:, 3], self._walls_near(spec.range), None, spec.range)
            bodies = cast_rays(origins, table[:, 3], None, self._person_bodies(), spec.range)
            unhidden = bodies >= table[:, 2] - BODY_RADIUS - 1e-6    # own body is the first hit
            seen = ((walls >= table[:, 2]) & unhidden
                    & (self.rng.random(len(table)) >= spec.miss_rate))
            noise = self.rng.normal(0.0, spec.noise, (len(table), 2))
            found = [(float(x), float(y), observed(looks[k], self.appearance_rng))
                     for k, (x, y) in zip(np.flatnonzero(seen), table[seen, :2] + noise[seen])]
        for _ in range(self.rng.poisson(spec.false_rate)):
            radius = spec.range * math.sqrt(self.rng.random())
            bearing = (self.rng.random() - 0.5) * spec.fov
            found.append((radius * math.cos(bearing), radius * math.sin(bearing),
                          anyone(self.appearance_rng)))
        return found

    def ground_truth(self) -> list[tuple[str, float, float]]:
        """(id, x, y) in the world frame of the people in the world now."""
        return [(p.id, p.x, p.y) for p in self.people if p.in_world]


def _check_floor(scenario: Scenario, floor: Floor) -> None:
    """Refuse a scenario written for another floor or map, naming its file and line."""
    if scenario.floor is not None and scenario.floor != floor.name:
        raise ScenarioError(f"{scenario.where_field('floor')}: scenario.floor: the scenario is "
                            f"written for floor '{scenario.floor}', not '{floor.name}'; run it "
                            f"on '{scenario.floor}' or drop the field")
    if scenario.map is not None and scenario.map != floor.source:
        raise ScenarioError(f"{scenario.where_field('map')}: scenario.map: the scenario is "
                            f"written for the map {scenario.map}, not "
                            f"{floor.source or 'floor ' + repr(floor.name)}; run it there "
                            f"(drop --map) or drop the field")


def _check_places(scenario: Scenario, floor: Floor) -> None:
    """Fail early, naming file, line and field, when a scenario uses a place the floor lacks."""
    for index, plan in enumerate(scenario.people):
        fields = [("at", plan.at), ("exit", plan.exit)]
        for number, step in enumerate(plan.steps):
            label = f"steps[{number}]"
            if isinstance(step, Walk):
                fields += [(f"{label}.walk", p) for p in step.waypoints]
            elif isinstance(step, Leave) and step.to is not None:
                fields.append((f"{label}.leave", step.to))
            elif isinstance(step, Follow) and step.goal is not None:
                fields.append((f"{label}.follow.goal", step.goal))
            elif isinstance(step, MakeWay) and step.to is not None:
                fields.append((f"{label}.make_way", step.to))
            elif isinstance(step, Lead):
                fields += [(f"{label}.lead", p) for p in step.waypoints]
            elif isinstance(step, Shop):
                fields += [(f"{label}.shop", p) for p in step.places]
                if step.prefix is not None and not any(name.startswith(step.prefix)
                                                       for name in floor.places):
                    raise ScenarioError(
                        f"{scenario.where(index)}: person '{plan.id}'.{label}.shop: floor "
                        f"'{floor.name}' has no place starting with '{step.prefix}'; places: "
                        f"{', '.join(sorted(floor.places))}")
        for name, where in fields:
            if isinstance(where, str) and where not in floor.places:
                raise ScenarioError(
                    f"{scenario.where(index)}: person '{plan.id}'.{name}: floor '{floor.name}' "
                    f"has no place '{where}'; places: {', '.join(sorted(floor.places))}")


__all__ = ["World", "ScreenState"]
