"""How simulated people move among each other: social forces (Helbing and Molnár 1995, with the
group coherence of Moussaïd et al. 2010) on top of each person's script, then a hard rule that
nobody overlaps anybody or the robot.

Each substep every person's script (`robots.sim.people`) says where they *want* to be; that
move over the substep is their desired velocity. A person's actual velocity is the desired one
plus a deviation that the social forces drive and that relaxes back with time `tau`:
`du/dt = -u / tau + F`. Without anyone near, F is zero and the person walks exactly as scripted
(so a lone person's run is unchanged); near others the forces make them slow, swerve and pass.

The forces on a person come from
- other people: the elliptical repulsive potential of Helbing and Molnár, `V0 exp(-b / sigma)`,
  whose semi-minor axis `b` shrinks with where the other is walking, weaker outside the
  person's field of view (we take the walk *relative* to the other, so that a walker
  anticipates a standing obstacle too); a person avoids the other's cart as a wall (below);
- walls and shelves (the floor's segments) and carts: `A exp(-gap / B)` from the nearest point
  (walls push walkers only: someone standing against a wall stays there);
- the robot, like another walker, scaled by the person's `yielding` trait (0 .. 1, drawn per
  person from a Beta distribution, `robots.sim.traits`): yielding people keep farther from it
  and also stand for it (`SimPerson._gives_way`); steps whose point is the robot (approach,
  answer, follow, lead, wait to be called, make way) feel no force from it;
- the group (people with the same `group`): attraction to the others' centre once farther than
  `(n - 1) / 2` m, as in Moussaïd's coherence term.
Forces below `comfort` m/s² are ignored (people do not drift apart while standing).

After the move, overlaps are pushed apart: bodies (0.2 m) and carts of different people, and
anybody with the robot's footprint (which does not move), and bodies out of walls; a person
whose overlap survives the pushing goes back to where they stood before the substep. A person
appears only once their spot is free. So people never pass through one another or the robot.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robots.sim.people import BLOCKED_PATIENCE, BODY_RADIUS, SimPerson
from robots.sim.scenario import Answer, Approach, Follow, Lead, MakeWay, WaitForCall
from robots.sim.wall_index import WallIndex

if TYPE_CHECKING:
    from robots.sim.scenario import Scenario
    from robots.sim.world import World

ROBOT_ATTENDED = (Approach, Answer, Follow, Lead, WaitForCall, MakeWay)
PUSH_ROUNDS = 8            # rounds of pushing overlaps apart before the fallback
OVERLAP_SLACK = 1e-6       # m of overlap that counts as touching
BLOCKED_SHARE = 0.25       # moved less than this share of the wish: held up by the crowd
HEADWAY_WINDOW = 1.0       # s over which headway and wish are averaged for that
TRAIT_STREAM = 0x7E1D      # seeds each person's trait generator with the run's seed and index
_NO_DEVIATION = (0.0, 0.0)
_EPS = 1e-4                # m, the step of the potential's numerical gradient
_SHIFT_X = np.array([_EPS, -_EPS, 0.0, 0.0])[:, None, None]   # the gradient's four points
_SHIFT_Y = np.array([0.0, 0.0, _EPS, -_EPS])[:, None, None]


@dataclass(frozen=True)
class CrowdParams:
    """Parameters of the social forces (SI units)."""
    tau: float = 0.5              # s, relaxation of the deviation (Helbing and Molnár)
    v0: float = 2.1               # m²/s², strength of the person-person potential
    sigma: float = 0.3            # m, its range
    step_time: float = 1.0        # s, how far ahead the walk relative to another shapes the
                                  # potential (relative velocity, so a walker anticipates)
    fov: float = math.radians(200.0)   # field of view; outside it forces count `behind`
    behind: float = 0.5
    wall_strength: float = 2.0    # m/s²
    wall_range: float = 0.05      # m
    wall_reach: float = 0.5       # m of gap beyond which walls are ignored
    robot_gain: tuple[float, float] = (0.6, 2.0)   # v0 factor at yielding 0 and 1
    group_pull: float = 1.0       # m/s², coherence
    group_repulsion: float = 0.3  # share of the repulsion between members of one group
    comfort: float = 0.1          # m/s²; weaker total forces are ignored by a walker
    comfort_standing: float = 0.5   # m/s², the same for someone standing
    evade: float = 1.0            # share of a repulsion added sideways, to pass the other
    overspeed: float = 1.3        # a person walks at most this times their scripted speed
    min_cap: float = 0.6          # m/s a standing person may be pushed at


class Crowd:
    """Steps the people of a world: scripts, then social forces and the no-overlap rule.
    With `social=False` the scripts alone move them (people who script exact paths)."""

    def __init__(self, social: bool = True, params: CrowdParams = CrowdParams()) -> None:
        self.social = social
        self.params = params
        self._deviation: dict[int, tuple[float, float]] = {}
        # per person: the averaged velocity (x, y) and the averaged wish
        self._headway: dict[int, tuple[tuple[float, float], float]] = {}
        self._walls: WallIndex | None = None
        self._walls_memo: tuple | None = None     # (index, positions, `_walls_at`'s answer)
        self._strengths: dict[tuple, np.ndarray] = {}   # repulsion shares, by the groups
        self._cos_half_fov = math.cos(params.fov / 2)

    @classmethod
    def for_scenario(cls, people: list[SimPerson], scenario: "Scenario | None",
                     seed: int) -> "Crowd":
        """The crowd of a world: social unless the scenario scripts exact paths; each
        person whose plan fixes neither `yielding` nor `give_way` draws their yielding from
        the scenario's Beta distribution, from a generator of their own (seed, index)."""
        a, b = scenario.yielding if scenario is not None else (2.0, 2.0)
        for index, person in enumerate(people):
            if person.plan.yielding is None and person.plan.give_way is None:
                rng = np.random.default_rng([seed, index, TRAIT_STREAM])
                person.yielding = float(rng.beta(a, b))
        return cls(social=scenario is None or scenario.motion == "social")

    def step(self, h: float, world: "World") -> None:
        """Advance every person of the world by h seconds."""
        people = world.people
        if not self.social:
            for person in people:
                person.step(h, world)
            return
        before = {id(p): (p.x, p.y, p.heading, p.cart_heading) for p in people}
        present_before = {id(p) for p in people if p.in_world}
        for person in people:
            if (not person.in_world and not person.gone and person.due(world.t)
                    and not self._room_at(person, world)):
                continue        # their spot is taken: they appear once it is free
            person.step(h, world)
        walking = [p for p in people if p.in_world and id(p) in present_before]
        if walking:
            self._apply_forces(walking, before, h, world)
        present = [p for p in people if p.in_world]
        if present:
            self._keep_apart(present, before, present_before, world)
            self._track_blocking(walking, before, h)

    # -- forces ----------------------------------------------------------------------------

    def _apply_forces(self, people: list[SimPerson], before: dict, h: float,
                      world: "World") -> None:
        """Move each person from where they stood by (wish + deviation) * h."""
        # one table, one conversion: where they stood, where their script put them, their
        # deviation, scripted speed and how long they have been held up
        table = np.array([(*before[id(person)][:2], person.x, person.y,
                           *self._deviation.get(id(person), _NO_DEVIATION), person.plan.speed,
                           person.blocked_for)
                          for person in people])
        start, deviation, scripted = table[:, 0:2], table[:, 4:6], table[:, 6]
        wish = (table[:, 2:4] - start) / h
        wished = np.hypot(wish[:, 0], wish[:, 1])
        held = table[:, 7] >= BLOCKED_PATIENCE
        walk = np.where(held[:, None], wish + deviation, wish)
        force = self.forces(people, start, wish, world, wished, walk)
        p = self.params
        u = (deviation + h * force) / (1.0 + h / p.tau)
        velocity = wish + u
        cap = np.maximum(np.where(wished > 1e-6, p.overspeed * scripted, 0.0), p.min_cap)
        speed = np.hypot(velocity[:, 0], velocity[:, 1])
        over = speed > cap
        if over.any():          # (most substeps nobody is over: nothing to scale)
            velocity[over] *= (cap[over] / speed[over])[:, None]
            speed = np.where(over, cap, speed)
        moved = start + velocity * h
        swerving = ((np.hypot(u[:, 0], u[:, 1]) > 1e-6) & (speed > 0.05)).tolist()
        # plain floats for the loop: numpy's scalar indexing costs more than the work
        rows = zip(people, wished.tolist(), (velocity - wish).tolist(), moved.tolist(),
                   velocity.tolist(), speed.tolist(), swerving)
        for person, wished_k, deviation_k, (x, y), (vx, vy), speed_k, swerves in rows:
            person.wished = wished_k
            self._deviation[id(person)] = tuple(deviation_k)
            person.x, person.y = x, y
            if swerves:                      # they face where they go
                person.heading = math.atan2(vy, vx)
                if person.plan.cart:
                    person.cart_heading = before[id(person)][3]    # one turn a substep
                    person.steer_cart(h)
            person.speed = speed_k if speed_k * h > 1e-9 else 0.0

    def forces(self, people: list[SimPerson], positions: np.ndarray, wish: np.ndarray,
               world: "World", wished: np.ndarray, walk: np.ndarray) -> np.ndarray:
        """Social force (m/s²) on each person, (n, 2). `wished`: the length of each wish;
        `walk`: each one's walk as the others see it (`_walker_forces`)."""
        from_people, from_robot = self._walker_forces(people, positions, wish, walk, world)
        force = (from_people
                 + self._wall_forces(positions, wished, world)
                 + self._cart_forces(people, positions, wish)
                 + from_robot
                 + self._group_forces(people, positions, wish))
        standing = wished < 1e-6
        comfort = np.where(standing, self.params.comfort_standing, self.params.comfort)
        weak = np.hypot(force[:, 0], force[:, 1]) < comfort
        force[weak] = 0.0
        for k, person in enumerate(people):
            if isinstance(person.current_step, MakeWay):
                force[k] = 0.0          # a group in the way stands until it steps aside
        return force

    def _potential_force(self, rx: np.ndarray, ry: np.ndarray, vx: np.ndarray, vy: np.ndarray,
                         wx: np.ndarray, wy: np.ndarray, strength: np.ndarray
                         ) -> tuple[np.ndarray, np.ndarray]:
        """-grad of `V0 exp(-b / sigma)` over the relative positions (rx, ry), given the
        others' walks relative to one's own (vx, vy) and one's own (wx, wy), weighted by the
        field of view: the force's x and y; b is Helbing and Molnár's elliptical semi-minor
        axis. x and y on contiguous tables of their own (numpy's arithmetic on interleaved
        columns costs twice), negations folded into divisions and comparisons (`x / -c` is
        `-(x / c)`, `0.5 * x / c` is `x / (2 c)`, both exactly): the same floats."""
        p = self.params
        step_x, step_y = vx * p.step_time, vy * p.step_time
        travel = np.hypot(step_x, step_y)
        # the four shifted positions of the numerical gradient at once, (4, n, m)
        qx, qy = rx + _SHIFT_X, ry + _SHIFT_Y
        distance = np.hypot(qx, qy)
        later = np.hypot(qx - step_x, qy - step_y)
        b2 = np.sqrt(np.maximum((distance + later) ** 2 - travel ** 2, 1e-12))   # 2 b
        values = strength * p.v0 * np.exp(b2 / (-2.0 * p.sigma))
        speed = np.hypot(wx, wy)            # for both below
        weight = self._view_weight(rx, ry, wx, wy, speed)
        fx = (values[0] - values[1]) / (-2 * _EPS) * weight
        fy = (values[2] - values[3]) / (-2 * _EPS) * weight
        side_x, side_y = self._sideways(fx, fy, rx, ry, wx, wy, speed)
        return fx + side_x, fy + side_y

    def _sideways(self, fx: np.ndarray, fy: np.ndarray, rx: np.ndarray, ry: np.ndarray,
                  wx: np.ndarray, wy: np.ndarray, speed: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
        """A walker swerves past someone ahead: `evade` times the repulsion (fx, fy), across
        the walking direction (wx, wy), away from the side the other is on (to the right when
        dead ahead). (rx, ry) points from the other to the walker; `speed`: the length of each
        wish."""
        length = np.maximum(speed, 1e-12)
        ex, ey = wx / length, wy / length
        ahead = (rx * ex + ry * ey) < 0.0
        left = ey * rx - ex * ry >= 0.0               # the other is on the left, or dead ahead
        size = self.params.evade * np.hypot(fx, fy)
        size = np.where(ahead & (speed > 1e-6), size, 0.0)
        # the left normal of (ex, ey) is (-ey, ex); turned to the right for one on the left
        signed = np.where(left, -size, size)
        return -ey * signed, ex * signed

    def _view_weight(self, rx: np.ndarray, ry: np.ndarray, wx: np.ndarray, wy: np.ndarray,
                     speed: np.ndarray) -> np.ndarray:
        """1 for what lies in the walking direction's (wx, wy) field of view, `behind`
        otherwise (and for a person standing still). (rx, ry) points from what is seen to the
        walker: the seen direction negated, which the cosine's test takes exactly; `speed`:
        the length of each wish."""
        distance = np.hypot(rx, ry)
        cosine = (wx * rx + wy * ry) / np.maximum(speed * distance, 1e-12)
        seen = (speed > 1e-6) & (cosine <= -self._cos_half_fov)
        return np.where(seen, 1.0, self.params.behind)

    def _walker_forces(self, people, positions, wish, walk, world: "World"
                       ) -> tuple[np.ndarray, np.ndarray]:
        """The potential forces (n, 2) from the other people and from the robot, evaluated
        together: each person's row holds the others, then the robot (when anybody minds
        it). The ellipse is shaped by the other's walk as one sees it (`walk`: the wish, or
        for someone held up by others for BLOCKED_PATIENCE the wish plus the deviation, how
        they actually move; the robot's velocity) less one's own wish. By the wish alone,
        two people held up facing each other each kept seeing the other rush at them and
        stood frozen 2.4 m apart for 29 s (follow benchmark, crowd10 seed 1)."""
        n = len(people)
        gains = self._robot_gains(people)
        with_people, with_robot = n >= 2, bool(gains.any())
        if not (with_people or with_robot):
            return np.zeros((n, 2)), np.zeros_like(positions)
        # the others' positions and walks, one row each: the people, then the robot
        body = world.body
        robot = (body.x, body.y, body.v * math.cos(body.th), body.v * math.sin(body.th))
        others = np.array(robot, ndmin=2)
        if with_people:
            own = np.concatenate((positions, walk), axis=1)
            others = np.concatenate((own, others)) if with_robot else own
        x, y, wx, wy = positions[:, 0:1], positions[:, 1:2], wish[:, 0:1], wish[:, 1:2]
        rx, ry = x - others[:, 0], y - others[:, 1]
        vx, vy = others[:, 2] - wx, others[:, 3] - wy   # the other's walk less one's wish
        strengths = [self._group_strength(people)] if with_people else []
        if with_robot:
            self._shrink_to_footprint(rx[:, -1], ry[:, -1], body.radius)
            strengths.append(gains[:, None])
        strength = strengths[0] if len(strengths) == 1 else np.concatenate(strengths, axis=1)
        fx, fy = self._potential_force(rx, ry, vx, vy, wx, wy, strength)
        from_people, from_robot = np.zeros((n, 2)), np.zeros_like(positions)
        if with_people:
            between = np.stack((fx[:, :n], fy[:, :n]), axis=-1)
            between[np.arange(n), np.arange(n)] = 0.0
            from_people = np.add.reduce(between, axis=1)     # what between.sum(axis=1) does
        if with_robot:
            from_robot = np.stack((fx[:, -1], fy[:, -1]), axis=-1)
        return from_people, from_robot

    def _group_strength(self, people) -> np.ndarray:
        """The repulsion's share between each two people (n, n): `group_repulsion` within a
        group, 1 otherwise."""
        groups = tuple(p.plan.group for p in people)
        strength = self._strengths.get(groups)
        if strength is None:        # the same people walk for many substeps: kept per groups
            same = np.array([[a is not None and a == b for b in groups] for a in groups])
            strength = np.where(same, self.params.group_repulsion, 1.0)
            strength.flags.writeable = False
            if len(self._strengths) > 64:
                self._strengths.clear()
            self._strengths[groups] = strength
        return strength

    def _wall_forces(self, positions: np.ndarray, wished: np.ndarray, world: "World"
                     ) -> np.ndarray:
        """Walls keep walkers off; someone standing against a wall stays (the hard rule
        still keeps them out of it)."""
        p = self.params
        out = np.zeros_like(positions)
        near, points = self._walls_at(positions, world)
        if len(near) == 0:      # a zero force, as the far ones get below (its sign aside,
            return out          # which the comfort threshold makes + 0 when it is all)
        away = positions[near] - points
        distance = np.maximum(np.hypot(away[:, 0], away[:, 1]), 1e-9)
        gap = distance - BODY_RADIUS
        size = np.where(gap < p.wall_reach,
                        p.wall_strength * np.exp(-np.maximum(gap, 0.0) / p.wall_range), 0.0)
        size[wished[near] < 1e-6] = 0.0
        out[near] = away * (size / distance)[:, None]
        return out

    def _wall_index(self, world: "World") -> WallIndex:
        """The floor's walls, bucketed for the reach of the wall force (built once)."""
        segments = world.floor.segments
        if self._walls is None or self._walls.segments is not segments:
            self._walls = WallIndex(segments, reach=BODY_RADIUS + self.params.wall_reach)
        return self._walls

    def _walls_at(self, positions: np.ndarray, world: "World"
                  ) -> tuple[np.ndarray, np.ndarray]:
        """The indices of the positions (n, 2) that may be within the wall force's reach (by
        the index's lower bounds of their wall distance), and their nearest wall points.
        Kept for the positions last asked about: a substep's forces ask about where the last
        round of pushing apart left everyone, which that round asked about already."""
        walls = self._wall_index(world)
        key = positions.tobytes()
        if self._walls_memo is not None and self._walls_memo[:2] == (walls, key):
            return self._walls_memo[2]
        bounds = walls.lower_bounds(positions)
        near = np.flatnonzero(bounds < BODY_RADIUS + self.params.wall_reach)
        found = near, walls.nearest_points(positions[near])
        self._walls_memo = (walls, key, found)
        return found

    def _cart_forces(self, people, positions, wish) -> np.ndarray:
        """Other people's carts push like walls do. Pair by pair in plain floats (numpy's
        scalar indexing costs more than the work): the same hypot (numpy's), differences,
        products and sums in the same order."""
        p = self.params
        out = np.zeros_like(positions)
        carts = [(k, c) for k, person in enumerate(people) for c in person.cart_circles()]
        if not carts:
            return out
        pairs = self._within_reach(positions, carts)
        at, walks = positions.tolist(), wish.tolist()
        for i, c in pairs:
            owner, (cx, cy, radius) = carts[c]
            if owner != i:
                rx, ry = at[i][0] - cx, at[i][1] - cy
                distance = float(np.hypot(rx, ry))
                gap = distance - radius - BODY_RADIUS
                if gap < p.wall_reach and distance > 1e-9:
                    weight = self._view_weight_of(-rx, -ry, *walks[i])
                    size = weight * p.wall_strength * math.exp(-max(gap, 0.0) / p.sigma)
                    out[i, 0] += size * rx / distance
                    out[i, 1] += size * ry / distance
        return out

    def _view_weight_of(self, tx: float, ty: float, wx: float, wy: float) -> float:
        """`_view_weight` of one direction (tx, ty) for one wish (wx, wy), in plain floats
        but numpy's hypot (math.hypot rounds differently)."""
        speed = float(np.hypot(wx, wy))
        distance = float(np.hypot(tx, ty))
        cosine = (wx * tx + wy * ty) / max(speed * distance, 1e-12)
        seen = speed > 1e-6 and cosine >= self._cos_half_fov
        return 1.0 if seen else self.params.behind

    def _within_reach(self, positions: np.ndarray, carts: list) -> list[tuple[int, int]]:
        """(person, cart) index pairs, in the order of a loop over people then carts, that
        may be within the wall force's reach: a margin over the exact test, which the caller
        makes on these pairs alone (most carts are far from most people)."""
        circles = np.array([c for _, c in carts])
        dx = positions[:, 0:1] - circles[None, :, 0]
        dy = positions[:, 1:2] - circles[None, :, 1]
        gap = np.hypot(dx, dy) - circles[None, :, 2] - BODY_RADIUS
        people, near = np.nonzero(gap < self.params.wall_reach + 1e-6)
        return list(zip(people.tolist(), near.tolist()))

    def _robot_gains(self, people) -> np.ndarray:
        """How much each person minds the robot as another walker (n,), by how much they
        yield to it; 0 while their step is about the robot."""
        low, high = self.params.robot_gain
        return np.array([0.0 if isinstance(p.current_step, ROBOT_ATTENDED)
                         else low + (high - low) * p.yielding for p in people])

    @staticmethod
    def _shrink_to_footprint(rx: np.ndarray, ry: np.ndarray, radius: float) -> None:
        """Scale, in place, the positions (rx, ry) relative to the robot's centre: the
        potential is made for bodies of 0.2 m; widen it by the footprint's excess."""
        distance = np.hypot(rx, ry)
        shrink = np.maximum(distance - (radius - BODY_RADIUS), 1e-3) / np.maximum(distance, 1e-9)
        rx *= shrink
        ry *= shrink

    def _group_forces(self, people, positions, wish) -> np.ndarray:
        out = np.zeros_like(positions)
        members: dict[str, list[int]] = {}
        for k, person in enumerate(people):
            if person.plan.group is not None:
                members.setdefault(person.plan.group, []).append(k)
        for group in members.values():
            if len(group) < 2:
                continue
            for k in group:
                if np.hypot(*wish[k]) < 1e-6:
                    continue
                others = positions[[j for j in group if j != k]].mean(axis=0)
                rel = others - positions[k]
                distance = float(np.hypot(*rel))
                if distance > (len(group) - 1) / 2.0:
                    out[k] += self.params.group_pull * rel / distance
        return out

    # -- the hard rule ---------------------------------------------------------------------

    def _keep_apart(self, people: list[SimPerson], before: dict, present_before: set,
                    world: "World") -> None:
        """Push overlapping bodies, carts and footprint apart; send back whoever still
        overlaps (their place before the substep was free); someone who appeared this substep
        and still overlaps appears later."""
        for _ in range(PUSH_ROUNDS):
            pushed = self._push_once(people, world)
            if pushed is None or self._settled(people, world, *pushed):
                return
        for _ in range(len(people) + 1):
            stuck = self._overlapping(people, world)
            if not stuck:
                return
            for person in stuck:
                if id(person) in present_before:
                    if person.plan.cart:     # its turn this substep is undone: the other way
                        person.block_cart_turn(math.remainder(
                            person.cart_heading - before[id(person)][3], math.tau))
                    person.x, person.y, person.heading, person.cart_heading = before[id(person)]
                    person.speed = 0.0
                    self._deviation[id(person)] = _NO_DEVIATION
                else:                 # appeared this substep (their cart swung into someone)
                    person.hold_back(*before[id(person)])
                    people = [p for p in people if p is not person]

    def _circles(self, people: list[SimPerson], world: "World"):
        """Every body and cart circle (m, 3) with its owner's index; the robot is owner -1."""
        rows, owners = [], []
        for k, person in enumerate(people):
            circles = person.circles()
            rows.extend(circles)
            owners.extend([k] * len(circles))
        footprint = world.body.circles()    # one circle, or a rectangle's
        owners.extend([-1] * len(footprint))
        rows.extend(footprint.tolist())
        return np.array(rows, dtype=float), np.array(owners)

    def _overlaps(self, people, world):
        """Owners, the pairs' x and y differences, distances and depths (m, m), and the
        overlapping pairs (a, b) once each. x and y apart: the same differences, on
        contiguous tables."""
        circles, owners = self._circles(people, world)
        x, y, radius = circles[:, 0], circles[:, 1], circles[:, 2]
        dx = x[:, None] - x[None, :]
        dy = y[:, None] - y[None, :]
        distance = np.hypot(dx, dy)
        depth = radius[:, None] + radius[None, :] - distance
        other = owners[:, None] != owners[None, :]
        a, b = np.nonzero(other & (depth > OVERLAP_SLACK) & _above_diagonal(len(owners)))
        return owners, dx, dy, distance, depth, a, b

    def _push_once(self, people: list[SimPerson], world: "World") -> tuple | None:
        """One round of pushing apart; None when nothing overlapped, else what `_settled`
        needs: the circles' owners and depths, whether pairs overlapped and the pushes out
        of walls. The pairs' pushes in plain floats (numpy's scalar indexing costs more than
        the work): the same divisions, products and sums in the same order."""
        owners, dx, dy, distance, depth, a, b = self._overlaps(people, world)
        moves = [[0.0, 0.0] for _ in people]
        if len(a):
            pairs = zip(owners[a].tolist(), owners[b].tolist(), dx[a, b].tolist(),
                        dy[a, b].tolist(), distance[a, b].tolist(), depth[a, b].tolist())
            for oi, oj, rx, ry, gap, deep in pairs:
                nx, ny = (rx / gap, ry / gap) if gap > 1e-9 else (1.0, 0.0)
                deep = deep + 1e-4
                px, py = nx * deep, ny * deep
                if oi >= 0 and oj >= 0:
                    moves[oi][0] += px / 2
                    moves[oi][1] += py / 2
                    moves[oj][0] -= px / 2
                    moves[oj][1] -= py / 2
                elif oi >= 0:
                    moves[oi][0] += px
                    moves[oi][1] += py
                else:
                    moves[oj][0] -= px
                    moves[oj][1] -= py
        walls = self._wall_overlaps(people, world)
        for k, (px, py) in walls.items():
            moves[k][0] += px
            moves[k][1] += py
        for person, (mx, my) in zip(people, moves):
            person.x += mx
            person.y += my
        if not len(a) and not walls:
            return None
        return owners, depth, len(a) > 0, walls

    def _settled(self, people: list[SimPerson], world: "World", owners: np.ndarray,
                 depth: np.ndarray, pairs: bool, walls: dict) -> bool:
        """True when the next round would find no overlap, so move nobody: this round
        pushed bodies out of walls alone, no two circles were nearer than the two longest
        pushes (nobody else moved), and each person pushed is now clear of every wall.
        Whatever is in doubt says False: the next round runs and decides. (The round after
        a wall's push found nothing nine times in ten: a whole round spared.)"""
        if pairs:
            return False
        longest = max(math.hypot(px, py) for px, py in walls.values())
        apart = -depth[owners[:, None] != owners[None, :]].max()
        if not apart > 2.0 * longest:          # (the overlap's slack absorbs the rounding)
            return False
        index = self._wall_index(world)
        clear = BODY_RADIUS - OVERLAP_SLACK / 2.0
        return all(index.clear_of(people[k].x, people[k].y, clear) for k in walls)

    def _wall_overlaps(self, people: list[SimPerson], world: "World") -> dict:
        """Pushes that take bodies out of walls, by person index."""
        positions = np.array([(p.x, p.y) for p in people])
        # those within the force's reach, a wider test than the overlap's (the rest are
        # farther than BODY_RADIUS, the overlap's distance, from every wall)
        near, points = self._walls_at(positions, world)
        if len(near) == 0:
            return {}
        away = positions[near] - points
        distance = np.hypot(away[:, 0], away[:, 1])
        inside = np.flatnonzero((distance < BODY_RADIUS - OVERLAP_SLACK) & (distance > 1e-9))
        if not len(inside):
            return {}
        # plain floats: the same division, sum and products as on numpy's scalars
        rows = zip(near[inside].tolist(), away[inside].tolist(), distance[inside].tolist())
        return {k: (ax / gap * (BODY_RADIUS - gap + 1e-4), ay / gap * (BODY_RADIUS - gap + 1e-4))
                for k, (ax, ay), gap in rows}

    def _overlapping(self, people: list[SimPerson], world: "World") -> list[SimPerson]:
        """People whose body or cart overlaps another's or the robot's footprint."""
        owners, _, _, _, _, a, b = self._overlaps(people, world)
        stuck = {int(o) for o in np.concatenate([owners[a], owners[b]]) if o >= 0}
        return [people[k] for k in sorted(stuck)]

    def _room_at(self, person: SimPerson, world: "World") -> bool:
        """True when a person appearing now overlaps nobody (with their cart) and not the
        robot."""
        present = [p for p in world.people if p.in_world]
        circles = person.circles()
        others = [(p.x, p.y, BODY_RADIUS) for p in present]
        others += [c for p in present for c in p.cart_circles()]
        others.extend(tuple(c) for c in world.body.circles())
        for x, y, r in circles:
            for ox, oy, orad in others:
                if math.hypot(x - ox, y - oy) < r + orad - OVERLAP_SLACK:
                    return False
        return True

    def _track_blocking(self, people: list[SimPerson], before: dict, h: float) -> None:
        """`blocked_for`: seconds a person walking on has made less headway than a quarter of
        what their script wished, both averaged over about HEADWAY_WINDOW s (so a script can
        count a place taken by others as reached). Averaged, not per substep: someone pushed
        to and fro at the edge of a spot the robot stands on moves every substep and gets
        nowhere (a stand-in who wanted to stand where the robot stands kept trying for good,
        and the robot, which never drives at a person inside its minimum, waited for her)."""
        k = min(h / HEADWAY_WINDOW, 1.0)
        for person in people:
            x0, y0 = before[id(person)][:2]
            step_x, step_y = (person.x - x0) / h, (person.y - y0) / h
            (head_x, head_y), wished = self._headway.get(id(person), ((0.0, 0.0), 0.0))
            head_x = head_x + k * (step_x - head_x)
            head_y = head_y + k * (step_y - head_y)
            wished = wished + k * (person.wished - wished)
            self._headway[id(person)] = ((head_x, head_y), wished)
            if person.wished > 1e-6 and math.hypot(head_x, head_y) < BLOCKED_SHARE * wished:
                person.blocked_for += h
            else:
                person.blocked_for = 0.0


_UPPER: dict[int, np.ndarray] = {}


def _above_diagonal(m: int) -> np.ndarray:
    """(m, m) True above the diagonal: each pair of circles once (kept per size)."""
    upper = _UPPER.get(m)
    if upper is None:
        upper = _UPPER[m] = np.triu(np.ones((m, m), dtype=bool), 1)
    return upper


__all__ = ["Crowd", "CrowdParams"]
