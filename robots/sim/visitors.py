"""Simulated visitors with hidden propensities (issue 27): passers-by who walk through the
hallway and may come closer to the robot — how likely depends on what the robot does and on
who they are, which the robot never sees; it sees only whether they came.

A scenario's `[visitors]` table (docs/scenarios.md) sets how many pass, when, and the
distributions each person's propensities are drawn from, per kind of visitor (single people,
members of groups) and optionally per period of the day:

    [visitors]
    count = 40                  # passers-by (groups count as one arrival each)
    first = 35.0                # s: the first arrives
    every = [40.0, 80.0]        # s between arrivals, uniform
    from = [9.5, 0.5]           # where they come from and go to (places or [x, y])
    to = [-9.5, 0.5]
    group_share = 0.3           # share of arrivals that are groups (of 2 or 3)
    answers = ["yes", "4", "no"]    # what they press if they take part
    [visitors.people]           # the propensities of people walking alone:
    voice = [2, 5]              #   Beta(a, b) chance to come closer when called
    head = [1, 9]               #   ... when the robot's head (or body) turns to them
    drive = [1, 9]              #   ... when the robot drives towards them
    patience = [20.0, 60.0]     #   s they give the questions, uniform
    [visitors.groups]           # the same for members of groups (default: as people)
    [[visitors.period]]         # from `from` s on, other distributions (a shift, the evening)
    from = 3600.0
    people = { voice = [5, 2] }

A visitor decides once, at the first of these the robot gives them: with their chance for it
they come closer, else they walk on and pay the robot no more heed (a call they ignored is not
made up for by a look). Calls count within 7 m, looks and drives within 5 m; a look is the
gaze (head pan plus heading) resting within 15 degrees of them for a second.

Arrival times, group sizes and patience are drawn when the scenario is read (from
`visitors.seed`); the propensities are drawn when a person appears, from the person's own
random stream (the run's `--seed`), so each seed meets other people on the same timetable.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from robots.sim.scenario import Answer, Approach, Leave, PersonPlan, Point

if TYPE_CHECKING:
    from robots.sim.people import SimPerson
    from robots.sim.world import World

STIMULI = ("voice", "head", "drive")
HEAR = 7.0              # m: a call heard farther away does not count
SEE = 5.0               # m: a head turn or a drive towards the person farther away does not
GAZE = math.radians(15.0)    # the robot looks at the person when its gaze is this close
GAZE_HELD = 1.0         # s the gaze must rest on the person to count as turning to them
DRIVE_TOWARDS = 0.1     # m/s of the robot's speed towards the person that counts
STOP_AT = 0.5           # m from the robot's centre where a person who comes stops
GROUP_SPACING = 0.5     # m between members of a group walking side by side
GROUP_ROW = 0.6         # m a group's third member walks behind the two in front
DEFAULT_TRAITS = {"voice": (1.0, 1.0), "head": (1.0, 1.0), "drive": (1.0, 1.0),
                  "patience": (20.0, 60.0)}


@dataclass(frozen=True)
class Traits:
    """The distributions one kind of visitor's propensities are drawn from."""
    voice: tuple[float, float] = DEFAULT_TRAITS["voice"]     # Beta(a, b)
    head: tuple[float, float] = DEFAULT_TRAITS["head"]
    drive: tuple[float, float] = DEFAULT_TRAITS["drive"]
    patience: tuple[float, float] = DEFAULT_TRAITS["patience"]   # s, uniform low .. high


@dataclass(frozen=True)
class Visit:
    """Walk to `to`, reacting to the robot: on a stimulus, with the person's hidden chance for
    it, the step ends and the person comes closer (the next steps); else they walk on."""
    to: Point
    traits: Traits = field(default_factory=Traits)
    group: int = 1                  # the size of the person's group (1: alone)


def visitor_plans(table: dict, reader) -> tuple[PersonPlan, ...]:
    """The people of a `[visitors]` table; `reader` is the scenario reader (errors, numbers)."""
    label = "visitors"
    reader.check_keys(table, label, {"seed", "count", "first", "every", "from", "to",
                                     "group_share", "answers", "speed", "people", "groups",
                                     "period"})
    rng = np.random.default_rng(int(reader.number(table, "seed", f"{label}.seed", 0, 2**31, 0)))
    count = int(reader.number(table, "count", f"{label}.count", 1, 100000))
    first = reader.number(table, "first", f"{label}.first", 0.0, 1e7, 35.0)
    every = _pair(reader, table, "every", (40.0, 80.0), 1.0, 1e6)
    speed = _pair(reader, table, "speed", (0.8, 1.3), 0.05, 3.0)
    start = reader.point(table.get("from", [9.5, 0.5]), f"{label}.from")
    goal = reader.point(table.get("to", [-9.5, 0.5]), f"{label}.to")
    groups = reader.number(table, "group_share", f"{label}.group_share", 0.0, 1.0, 0.0)
    answers = table.get("answers", ["yes", "4", "no"])
    if not (isinstance(answers, list) and answers and all(isinstance(a, str) for a in answers)):
        raise reader.fail(f"{label}.answers", "must be a list of button texts")
    kinds = _kinds(reader, table, label)
    periods = _periods(reader, table, label, kinds)
    plans, t = [], first
    abreast = not (isinstance(start, str) or isinstance(goal, str))
    for arrival in range(count):
        size = int(rng.integers(2, 4)) if rng.random() < groups else 1
        traits = _traits_at(t, kinds, periods)["groups" if size > 1 else "people"]
        pace = float(rng.uniform(*speed))
        for member in range(size):
            patience = float(rng.uniform(*traits.patience))
            side, behind = _place_in_group(member, size)
            at, to = _beside(start, goal, side), _beside(goal, start, -side)
            steps = (Visit(to, traits, size), Approach(STOP_AT + 0.3 * member),
                     Answer(tuple(answers), delay=2.0, reach=1.2, timeout=patience),
                     Leave(to))
            plans.append(PersonPlan(id=f"visitor{arrival}" + (f"_{member}" if size > 1 else ""),
                                    appear=t + (behind if abreast else member * GROUP_SPACING)
                                    / pace,
                                    at=at, speed=pace, exit=to, steps=steps,
                                    group=f"visitor{arrival}" if size > 1 else None))
        t += float(rng.uniform(*every))
    return tuple(plans)


def _place_in_group(member: int, size: int) -> tuple[float, float]:
    """Where a group's member walks: metres to the left of the way, and behind the front row.
    Two walk abreast (as groups do where the way is free: Moussaïd et al. 2010); a third
    follows in the middle behind them, since three abreast do not pass the robot in a 2.4 m
    hallway."""
    if size == 1:
        return 0.0, 0.0
    if member < 2:
        return (member - 0.5) * GROUP_SPACING, 0.0
    return 0.0, GROUP_ROW * (member - 1)


def _beside(point: Point, towards: Point, side: float) -> Point:
    """`point` moved `side` metres to the left of the way to `towards` (a group walks abreast,
    as groups do when the way is free: Moussaïd et al. 2010). A place name cannot be moved:
    then the members walk in file, one behind the other."""
    if side == 0.0 or isinstance(point, str) or isinstance(towards, str):
        return point
    dx, dy = towards[0] - point[0], towards[1] - point[1]
    norm = math.hypot(dx, dy)
    if norm < 1e-9:
        return point
    return (point[0] - dy / norm * side, point[1] + dx / norm * side)


def visit(person: "SimPerson", step: Visit, dt: float, world: "World") -> bool:
    """The handler of a Visit step (robots.sim.people): True once the person decides to come."""
    state = person.step_state
    if "chance" not in state:
        state["chance"] = _draw(person.rng, step.traits)      # hidden from the robot
        state["heard"] = len(world.utterances)
        state["gazed_since"] = None
    distance = person._distance_to_robot(world)
    if _stimulated(person, state, distance, world):
        return True
    if person._walk_towards(*person.resolve(step.to), dt, world=world):
        person.in_world = False              # walked past: gone for good
        person.gone = True
        person.index = len(person.steps)
    return False


def _stimulated(person, state: dict, distance: float, world: "World") -> bool:
    """The first stimulus the robot gives decides, with the person's chance for it."""
    if state.get("decided"):
        return False
    rng, chance = person.rng, state["chance"]
    said = len(world.utterances) - state["heard"]
    state["heard"] = len(world.utterances)
    if distance <= HEAR and said:
        return _decide(state, rng, chance["voice"])
    if distance > SEE:
        state["gazed_since"] = None
        return False
    body = world.body
    bearing = math.atan2(person.y - body.y, person.x - body.x)
    gaze = body.th + world.head_pan
    if abs(math.remainder(gaze - bearing, math.tau)) <= GAZE:
        since = state["gazed_since"] = (state["gazed_since"] if state["gazed_since"] is not None
                                        else world.t)
        if world.t - since >= GAZE_HELD - 1e-9:
            return _decide(state, rng, chance["head"])
    else:
        state["gazed_since"] = None
    towards = body.v * math.cos(math.remainder(bearing - body.th, math.tau))
    if towards >= DRIVE_TOWARDS:
        return _decide(state, rng, chance["drive"])
    return False


def _decide(state: dict, rng: np.random.Generator, chance: float) -> bool:
    state["decided"] = True
    return bool(rng.random() < chance)


def _draw(rng: np.random.Generator, traits: Traits) -> dict[str, float]:
    return {name: float(rng.beta(*getattr(traits, name))) for name in STIMULI}


# -- reading the table ---------------------------------------------------------------------

def _pair(reader, table: dict, key: str, default: tuple[float, float], low: float,
          high: float, label: str = "visitors", ordered: bool = True) -> tuple[float, float]:
    value = table.get(key, list(default))
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        value = [value, value]
    if not (isinstance(value, list) and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
            and low <= min(value) and max(value) <= high
            and (value[0] <= value[1] or not ordered)):
        shape = "[low, high] with low <= high" if ordered else "[a, b]"
        raise reader.fail(f"{label}.{key}", f"= {value!r} must be {shape}, each within "
                          f"{low} .. {high}")
    return float(value[0]), float(value[1])


def _traits(reader, table, label: str, base: Traits) -> Traits:
    if table is None:
        return base
    if not isinstance(table, dict):
        raise reader.fail(label, "must be a table such as { voice = [2, 5] }")
    reader.check_keys(table, label, set(DEFAULT_TRAITS))
    values = {}
    for name in STIMULI:
        a, b = _pair(reader, table, name, getattr(base, name), 0.0, 1e6, label, ordered=False)
        if a <= 0 or b <= 0:
            raise reader.fail(f"{label}.{name}", f"= {[a, b]!r}: Beta parameters must be > 0, "
                              "e.g. [2, 5]")
        values[name] = (a, b) if name in table else getattr(base, name)
    values["patience"] = _pair(reader, table, "patience", base.patience, 0.0, 1e5, label)
    return Traits(**values)


def _kinds(reader, table: dict, label: str) -> dict[str, Traits]:
    people = _traits(reader, table.get("people"), f"{label}.people", Traits())
    groups = _traits(reader, table.get("groups"), f"{label}.groups", people)
    return {"people": people, "groups": groups}


def _periods(reader, table: dict, label: str,
             kinds: dict[str, Traits]) -> list[tuple[float, dict[str, Traits]]]:
    """(from, kinds) per `[[visitors.period]]`, in time order; each starts from the table's."""
    found = []
    for index, period in enumerate(table.get("period", [])):
        where = f"{label}.period[{index}]"
        if not isinstance(period, dict):
            raise reader.fail(where, "must be a table ([[visitors.period]])")
        reader.check_keys(period, where, {"from", "people", "groups"})
        start = reader.number(period, "from", f"{where}.from", 0.0, 1e7)
        people = _traits(reader, period.get("people"), f"{where}.people", kinds["people"])
        # groups are like people unless the scenario says otherwise, in each period too
        alike = "groups" not in table
        groups = _traits(reader, period.get("groups"), f"{where}.groups",
                         people if alike else kinds["groups"])
        found.append((start, {"people": people, "groups": groups}))
    return sorted(found, key=lambda p: p[0])


def _traits_at(t: float, kinds: dict[str, Traits],
               periods: list[tuple[float, dict[str, Traits]]]) -> dict[str, Traits]:
    current = kinds
    for start, period_kinds in periods:
        if t >= start:
            current = period_kinds
    return current
