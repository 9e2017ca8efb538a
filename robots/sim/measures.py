"""What an evaluation measures in the simulated world: clearances, contacts and intrusions
into personal space, from the ground truth after every substep.

Distances are *gaps* between outlines: the robot's footprint (its profile radius, or the
oriented rectangle of a box-shaped base: robots/sim/outline.py) and a person's body circle (0.2 m, with their cart if they push one) or a wall segment. A gap of
zero is touching.

- **Clearance**: the smallest gap seen, to walls and to each person.
- **Contact**: the body was stopped by an obstacle (a bumper hit, `body.stalled`) or a gap
  reached zero (a person walking into the robot). Counted once per episode and obstacle (an
  episode lasts until the gap opens wider than 2 cm), with its time and whether the robot was
  driving.
- **Intrusion** into personal space: a gap below `personal_space` (0.45 m, Hall's intimate
  zone) while one side closes in: `by="robot"` when the robot drives towards the person,
  `by="person"` when the person walks towards the robot. Counted once per episode, person and
  side; `intrusion_seconds` adds up the time spent so.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robots.sim.people import BODY_RADIUS
from robots.sim.raycast import nearest_of_many_segments, nearest_segment

if TYPE_CHECKING:
    from robots.sim.world import World

PERSONAL_SPACE = 0.45     # m, gap between footprint and body
MOVING = 0.02             # m/s; slower counts as standing
NEAR_PEOPLE = 1.0         # m gap within which the robot's speed counts as "near people"
RELEASE = 0.02            # m; a contact lasts until the gap opens wider than this
NEAR_WALLS = 0.5          # m beyond the footprint within which World passes the walls


@dataclass(frozen=True)
class Contact:
    t: float              # s of sim time the contact began
    kind: str             # "wall" or "person"
    who: str              # "wall" or the person's id
    robot_moving: bool    # the robot was driving into it (else it was hit standing)
    part: int = 0         # what of the person touched: 0 their body, 1.. their cart's circles


@dataclass(frozen=True)
class Intrusion:
    t: float              # s of sim time the intrusion began
    person: str           # the person's id
    by: str               # "robot" (it closed in on the person) or "person" (closed in on it)


class Measures:
    """Running minima, events and totals; `World.step` updates them after each substep."""

    def __init__(self, personal_space: float = PERSONAL_SPACE,
                 near_people: float = NEAR_PEOPLE) -> None:
        self.personal_space = personal_space
        self.near_people = near_people
        self.min_wall_clearance = math.inf
        self.min_person_clearance: dict[str, float] = {}
        self.contacts: list[Contact] = []
        self.intrusions: list[Intrusion] = []
        self.intrusion_seconds = {"robot": 0.0, "person": 0.0}
        self.max_speed_near_people = 0.0          # m/s, |v| while a gap < near_people
        self._touching: set[tuple[str, str]] = set()
        self._intruding: set[tuple[str, str]] = set()
        self._bound: tuple | None = None     # (x, y, segments, gap bound) of the last bound

    # -- queries ---------------------------------------------------------------------------

    @property
    def min_clearance_to_people(self) -> float:
        """The smallest gap to anyone (inf when nobody was ever there)."""
        return min(self.min_person_clearance.values(), default=math.inf)

    def contact_count(self, kind: str | None = None) -> int:
        """Contacts of one kind ("wall", "person") or all."""
        return sum(1 for c in self.contacts if kind is None or c.kind == kind)

    def intrusion_count(self, by: str | None = None) -> int:
        """Intrusions by one side ("robot", "person") or all."""
        return sum(1 for i in self.intrusions if by is None or i.by == by)

    def summary(self) -> dict:
        """The figures as plain numbers, for a benchmark's table."""
        return {"min_wall_clearance": self.min_wall_clearance,
                "min_clearance_to_people": self.min_clearance_to_people,
                "contacts_wall": self.contact_count("wall"),
                "contacts_person": self.contact_count("person"),
                "intrusions_by_robot": self.intrusion_count("robot"),
                "intrusions_by_person": self.intrusion_count("person"),
                "intrusion_seconds_robot": self.intrusion_seconds["robot"],
                "intrusion_seconds_person": self.intrusion_seconds["person"],
                "max_speed_near_people": self.max_speed_near_people}

    # -- updating --------------------------------------------------------------------------

    def update(self, world: "World", dt: float, near_walls: np.ndarray | None = None) -> None:
        """Measure the world as it is after a substep of `dt` seconds. `near_walls` may hold
        every wall within `NEAR_WALLS` of the body's footprint (as `World.step` passes them);
        without it all walls are searched."""
        body = world.body
        if body.rectangle is not None:               # the real outline, not the circle
            segments = world.floor.segments if near_walls is None else near_walls
            if near_walls is not None and not len(near_walls) and (
                    self.min_wall_clearance > NEAR_WALLS):
                segments = world.floor.segments      # the exact value still counts
            gap_wall = self._outline_gap(body, segments)
        elif near_walls is None:
            gap_wall = nearest_of_many_segments(body.x, body.y, world.floor.segments) - body.radius
        elif len(near_walls):
            gap_wall = nearest_segment(body.x, body.y, near_walls) - body.radius
        elif self.min_wall_clearance > NEAR_WALLS:     # the exact value still counts
            gap_wall = nearest_of_many_segments(body.x, body.y, world.floor.segments) - body.radius
        else:
            gap_wall = math.inf                        # farther than the minimum: no news
        self.min_wall_clearance = min(self.min_wall_clearance, gap_wall)
        driving = abs(body.v) > MOVING
        heading = (math.cos(body.th) * math.copysign(1.0, body.v),
                   math.sin(body.th) * math.copysign(1.0, body.v))
        gaps, parts = {}, {}
        closest = math.inf
        for person in world.present_people():
            dx, dy = person.x - body.x, person.y - body.y
            centre = math.hypot(dx, dy)
            gap, part = body.gap_to_circle(person.x, person.y, BODY_RADIUS), 0
            if person.plan.cart:                                 # the cart is part of them
                for k, (cx, cy, radius) in enumerate(person.cart_circles(), 1):
                    cart_gap = body.gap_to_circle(cx, cy, radius)
                    if cart_gap < gap:
                        gap, part = cart_gap, k
            gaps[person.id] = gap
            parts[person.id] = part
            closest = min(closest, gap)
            if gap < self.min_person_clearance.get(person.id, math.inf):
                self.min_person_clearance[person.id] = gap
            if gap < self.personal_space:
                ux, uy = (dx / centre, dy / centre) if centre > 1e-9 else (0.0, 0.0)
                robot_closing = driving and heading[0] * ux + heading[1] * uy > 0.0
                towards = -(math.cos(person.heading) * ux + math.sin(person.heading) * uy)
                person_closing = person.speed > MOVING and towards > 0.0
                self._intrusion(world.t, dt, person.id, "robot", robot_closing)
                self._intrusion(world.t, dt, person.id, "person", person_closing)
            elif self._intruding:
                self._intruding.discard((person.id, "robot"))
                self._intruding.discard((person.id, "person"))
        if closest < self.near_people:
            self.max_speed_near_people = max(self.max_speed_near_people, abs(body.v))
        if body.stalled or self._touching or gap_wall <= RELEASE or closest <= RELEASE:
            self._contacts(world.t, body, gap_wall, gaps, parts)

    def _outline_gap(self, body, segments: np.ndarray) -> float:
        """The box-shaped footprint's gap to the walls; or, unless the body is stalled, a lower
        bound of it that is above both the smallest gap so far and RELEASE: the exact gap would
        change nothing then (the minimum stays, no wall contact begins or lasts), and it
        costs dozens of array operations per substep."""
        if not len(segments):
            return math.inf
        known = body.rectangle.known_gap(body.x, body.y, body.th, segments)
        if known is not None:
            return known
        if not body.stalled:
            bound = self._bound
            if bound is None or bound[2] is not segments or bound[:2] != (body.x, body.y):
                bound = self._bound = (body.x, body.y, segments, body.gap_bound(segments))
            if bound[3] > self.min_wall_clearance and bound[3] > RELEASE:
                return bound[3]
        return body.gap_to_walls(segments)

    def _intrusion(self, t: float, dt: float, person: str, by: str, now: bool) -> None:
        key = (person, by)
        if now:
            self.intrusion_seconds[by] += dt
            if key not in self._intruding:
                self._intruding.add(key)
                self.intrusions.append(Intrusion(t, person, by))
        else:
            self._intruding.discard(key)

    def _contacts(self, t: float, body, gap_wall: float, gaps: dict[str, float],
                  parts: dict[str, int]) -> None:
        """Touching: a gap at zero, or the obstacle nearest to a body stopped by a bumper.
        A new contact keeps which part of the person was nearest (`parts`): a judge of who
        closed in looks at that one, though the push that parts them may bring another nearer
        by the end of the tick."""
        touching = set()
        if gap_wall <= 0.0:
            touching.add(("wall", "wall"))
        touching |= {("person", pid) for pid, gap in gaps.items() if gap <= 0.0}
        if body.stalled:
            nearest = min(gaps.items(), key=lambda item: item[1], default=(None, math.inf))
            touching.add(("wall", "wall") if gap_wall <= nearest[1] else ("person", nearest[0]))
        for kind, who in self._touching:         # pressing on: the same contact goes on
            if (gap_wall if kind == "wall" else gaps.get(who, math.inf)) <= RELEASE:
                touching.add((kind, who))
        moving = body.stalled or abs(body.v) > MOVING
        for kind, who in sorted(touching - self._touching):
            self.contacts.append(Contact(t, kind, who, moving, parts.get(who, 0)))
        self._touching = touching

