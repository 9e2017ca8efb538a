"""Scenario files: who appears in the simulated world, where and when, and what they do.

The format is documented in `docs/scenarios.md`. This module only parses and checks the file
into plain dataclasses; `robots.sim.people` carries the script out and `robots.sim.world`
resolves place names against the floor. Every error names the file, the line of the person's
`[[person]]` header where there is one, and the field.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Union

from robots.exceptions import ScenarioError
from robots.sim.heeding import ANSWERS, Distribution
from robots.tomlfile import read_toml

Point = Union[str, tuple[float, float]]          # a place name or (x, y) in metres
Pose = Union[str, tuple[float, float, float]]    # a place name or (x, y, heading rad)


@dataclass(frozen=True)
class Walk:
    waypoints: tuple[Point, ...]
    route: bool = False           # walk around walls instead of straight


@dataclass(frozen=True)
class Pause:
    seconds: float


@dataclass(frozen=True)
class Approach:
    distance: float               # m, centre to centre, where the person stops


@dataclass(frozen=True)
class Answer:
    buttons: tuple[str, ...]      # one per prompt, in order (typed text on a typed prompt)
    delay: float = 2.0            # s after the prompt appears
    reach: float = 1.0            # m; farther away the person first steps closer
    timeout: float = math.inf     # s; give up and go on with the next step
    typing: float = 0.2           # s per character typed (typed prompts, value not a button)


@dataclass(frozen=True)
class WaitForCall:
    timeout: float                # s; without an utterance by then the person leaves


@dataclass(frozen=True)
class Leave:
    to: Point | None = None       # None: the person's exit
    route: bool = False           # walk around walls instead of straight


@dataclass(frozen=True)
class Follow:
    """Follow the robot along its trail, as a visitor follows a guide."""
    distance: float = 1.2               # m kept to the robot, along its trail
    after_call: bool = False            # start only once the robot has said something
    stop_after: float = math.inf        # s of following, then stand `stop_for` s (once)
    stop_after_m: float = math.inf      # or m walked while following
    stop_for: float = math.inf          # s standing before coming on (inf: for good)
    lag: float = 0.0                    # m farther behind while the robot drives
    until: float = math.inf             # s of following, then give up (the step ends)
    goal: Point | None = None           # where the robot is going, to know it arrived
    settle: float = 3.0                 # s the robot stands (near the goal) before the end
    timeout: float = math.inf           # s since the step began, then the step ends


@dataclass(frozen=True)
class MakeWay:
    """Stand (in a group, in the way) until asked to let the robot pass, then step aside."""
    to: Point | None = None             # where to step aside to; or, with None,
    aside: float = 0.0                  # m to step to the robot's `side`
    side: str | None = None             # "left" or "right" of the robot's heading
    asked: bool = True                  # react to the robot speaking while near
    near: float = 2.0                   # m, centre to centre: the robot counts as near
    delay: float = 1.0                  # s between being asked and stepping aside
    after: float = math.inf             # s; step aside by then anyway


@dataclass(frozen=True)
class Shop:
    """Walk between shelf places (around the shelves), dwelling at each."""
    places: tuple[Point, ...] = ()      # in order; or drawn by `prefix`
    prefix: str | None = None           # draw `count` places whose name starts with this
    count: int = 3
    dwell: tuple[float, float] = (5.0, 5.0)   # s at each place, uniform in [low, high]


@dataclass(frozen=True)
class Lead:
    """Walk a route (around walls) at the person's pace, for the robot to follow."""
    waypoints: tuple[Point, ...]
    dwell: float = 0.0                  # s standing at each waypoint
    after_call: bool = False            # start only once the robot has said something
    wait_beyond: float = math.inf       # m; stand and wait while the robot is farther


@dataclass(frozen=True)
class Sync:
    """Stand until another person has begun one of their steps (or has gone)."""
    person: str
    step: int = 0                       # index into that person's steps, from 0


Step = Union[Walk, Pause, Approach, Answer, WaitForCall, Leave, Follow, MakeWay, Shop, Lead,
             Sync]
STEP_KINDS = ("walk", "pause", "approach", "answer", "wait_for_call", "leave", "follow",
              "make_way", "shop", "lead", "sync")
STEP_OPTIONS = {
    "walk": {"route"},
    "leave": {"route"},
    "answer": {"delay", "reach", "timeout", "typing"},
    "follow": {"after_call", "stop_after", "stop_after_m", "stop_for", "lag", "until", "goal",
               "settle", "timeout"},
    "make_way": {"side", "asked", "near", "delay", "after"},
    "shop": {"count", "dwell"},
    "lead": {"dwell", "after_call", "wait_beyond"},
    "sync": {"step"},
}


@dataclass(frozen=True)
class PersonPlan:
    id: str
    appear: float                 # s of sim time
    at: Point
    speed: float                  # m/s
    exit: Point
    steps: tuple[Step, ...]
    line: int | None = None       # of the [[person]] header, for messages
    cart: bool = False            # pushes a shopping cart ahead
    give_way: bool | None = None  # stands while the robot is in their way (robots.sim.people);
                                  # None: the `yielding` trait decides
    yielding: float | None = None # 0 .. 1 how much they yield to the robot; None: drawn
    group: str | None = None      # people of one group keep together (robots.sim.crowd)
    looks_like: str | None = None # dressed like this other person (robots.sim.appearance)
    heeding: str | None = None    # how they answer the robot's "wait for me" when leading it
                                  # (robots.sim.heeding); None: drawn


@dataclass(frozen=True)
class Scenario:
    name: str
    description: str
    duration: float
    robot: Pose
    people: tuple[PersonPlan, ...]
    source: Path | None = None
    floor: str | None = None      # the floor the scenario is written for (None: any)
    map: Path | None = None       # the map_server map it is written for (absolute path)
    head_lines: dict[str, int] | None = None     # line of each [scenario] field, for messages
    motion: str = "social"        # "social": robots.sim.crowd; "scripted": exact paths
    yielding: tuple[float, float] = (2.0, 2.0)   # Beta(a, b) of the people's yielding trait
    heeding: Distribution = Distribution()       # of their heeding (robots.sim.heeding)

    def where(self, person_index: int | None = None) -> str:
        """'file:line' of the scenario or of one person's header, for messages."""
        place = str(self.source or "<scenario>")
        if person_index is not None and self.people[person_index].line:
            place += f":{self.people[person_index].line}"
        return place

    def where_field(self, key: str) -> str:
        """'file:line' of a field of the [scenario] table (the file alone if not written)."""
        line = (self.head_lines or {}).get(key)
        return f"{self.source or '<scenario>'}{':' + str(line) if line else ''}"


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file; a ScenarioError names the file, line and field."""
    path = Path(path)
    data, text = read_toml(path, ScenarioError, "scenario file")
    return parse_scenario(data, path, _person_lines(text), _head_lines(text))


def parse_scenario(data: dict, path: Path | str = "<scenario>",
                   person_lines: list[int] | None = None,
                   head_lines: dict[str, int] | None = None) -> Scenario:
    """Build a Scenario from parsed TOML; `path` and the lines only label errors (and a
    relative `map` is found beside `path`)."""
    reader = _Reader(Path(path), person_lines or [], head_lines or {})
    return reader.scenario(data)


def _head_lines(text: str) -> dict[str, int]:
    """Line numbers (1-based) of the keys written in the `[scenario]` table."""
    lines, inside = {}, False
    for number, line in enumerate(text.splitlines(), 1):
        header = re.match(r"\s*\[\s*\[?\s*([A-Za-z_.]+)", line)
        if header:
            inside = header.group(1) == "scenario"
            continue
        key = re.match(r"\s*([A-Za-z_][A-Za-z0-9_-]*)\s*=", line)
        if inside and key:
            lines.setdefault(key.group(1), number)
    return lines


def _person_lines(text: str) -> list[int]:
    """Line numbers (1-based) of the `[[person]]` headers, in order."""
    return [number for number, line in enumerate(text.splitlines(), 1)
            if re.match(r"\s*\[\[\s*person\s*\]\]", line)]


class _Reader:
    """Checks each field, naming file, line and field on the first error."""

    def __init__(self, path: Path, person_lines: list[int],
                 head_lines: dict[str, int] | None = None) -> None:
        self.path = path
        self.person_lines = person_lines
        self.head_lines = head_lines or {}
        self.where = str(path)

    def fail_head(self, key: str, why: str) -> ScenarioError:
        """An error in the [scenario] table, at the field's line where it was written."""
        line = self.head_lines.get(key)
        return ScenarioError(f"{self.path}{':' + str(line) if line else ''}: scenario.{key}: "
                             f"{why}")

    def fail(self, field_name: str, why: str) -> ScenarioError:
        return ScenarioError(f"{self.where}: {field_name}: {why}")

    def scenario(self, data: dict) -> Scenario:
        unknown = set(data) - {"scenario", "person", "visitors"}
        if unknown:
            raise self.fail(sorted(unknown)[0], "unknown table; allowed: [scenario], [[person]], "
                            "[visitors]")
        head = data.get("scenario", {})
        if not isinstance(head, dict):
            raise self.fail("scenario", "must be a table")
        self.check_keys(head, "scenario", {"name", "description", "duration", "robot", "floor",
                                           "map", "motion", "yielding", "heeding"})
        floor = head.get("floor")
        if floor is not None and (not isinstance(floor, str) or not floor):
            raise self.fail_head("floor", f"= {floor!r} must be a floor name such as "
                                 "\"office\" or \"store\"")
        map_path = self.map_path(head.get("map"))
        if floor is not None and map_path is not None:
            raise self.fail_head("map", "a scenario is written for a floor or for a map, not "
                                 "both; drop `floor` or `map`")
        duration = self.number(head, "duration", "scenario.duration", 1.0, 86400.0, 120.0)
        robot = self.pose(head.get("robot", "robot_home"), "scenario.robot")
        people_data = data.get("person", [])
        if not isinstance(people_data, list):
            raise self.fail("person", "must be an array of tables: [[person]]")
        people = tuple(self.person(entry, index) for index, entry in enumerate(people_data))
        self.where = str(self.path)
        if "visitors" in data:                # passers-by with hidden propensities (issue 27)
            from robots.sim.visitors import visitor_plans
            people += visitor_plans(data["visitors"], self)
        ids = [p.id for p in people]
        for pid in ids:
            if ids.count(pid) > 1:
                raise self.fail("person.id", f"'{pid}' is used twice; ids must be unique")
        self.check_syncs(people)
        return Scenario(name=str(head.get("name", self.path.stem)),
                        description=str(head.get("description", "")),
                        duration=duration, robot=robot, people=people, source=self.path,
                        floor=floor, map=map_path, head_lines=dict(self.head_lines),
                        motion=self.motion(head), yielding=self.beta(head),
                        heeding=self.heeding(head))

    def motion(self, head: dict) -> str:
        """How people move: "social" (social forces, never overlapping) or "scripted"."""
        value = head.get("motion", "social")
        if value not in ("social", "scripted"):
            raise self.fail_head("motion", f"= {value!r} must be \"social\" or \"scripted\"")
        return value

    def beta(self, head: dict) -> tuple[float, float]:
        """The Beta(a, b) distribution people's yielding trait is drawn from."""
        value = head.get("yielding", [2.0, 2.0])
        if (not isinstance(value, list) or len(value) != 2 or not all(_is_number(v) for v in value)
                or not all(0.05 <= v <= 100.0 for v in value)):
            raise self.fail_head("yielding", f"= {value!r} must be [a, b], the parameters of a "
                                 "Beta distribution, each 0.05 .. 100")
        return (float(value[0]), float(value[1]))

    def heeding(self, head: dict) -> Distribution:
        """The distribution people's heeding is drawn from (robots.sim.heeding)."""
        value = head.get("heeding", {})
        if not isinstance(value, dict):
            raise self.fail_head("heeding", f"= {value!r} must be a table such as "
                                 "{ never = 0.25, slow = 0.5, pace = [0.4, 0.55] }")
        base = Distribution()
        unknown = set(value) - set(base.__dataclass_fields__)
        if unknown:
            raise self.fail_head("heeding", f"unknown key {sorted(unknown)[0]!r}; allowed: "
                                 f"{', '.join(base.__dataclass_fields__)}")
        shares = {}
        for key in ("never", "slow"):
            share = value.get(key, getattr(base, key))
            if not _is_number(share) or not 0.0 <= share <= 1.0:
                raise self.fail_head("heeding", f"{key} = {share!r} must be a share 0 .. 1")
            shares[key] = float(share)
        ranges = {}
        for key, high in (("pace", 3.0), ("slow_for", 3600.0), ("patience", 3600.0)):
            pair = value.get(key, list(getattr(base, key)))
            if (not isinstance(pair, list) or len(pair) != 2
                    or not all(_is_number(v) and 0.0 < v <= high for v in pair)
                    or pair[0] > pair[1]):
                raise self.fail_head("heeding", f"{key} = {pair!r} must be [low, high], "
                                     f"0 < low <= high <= {high:g}")
            ranges[key] = (float(pair[0]), float(pair[1]))
        return Distribution(**shares, **ranges)

    def map_path(self, value) -> Path | None:
        """The scenario's `map`: a map_server .yaml, relative to the scenario file's folder."""
        if value is None:
            return None
        if not isinstance(value, str) or not value.endswith((".yaml", ".yml")):
            raise self.fail_head("map", f"= {value!r} must be the path of a map_server .yaml "
                                 "(relative to this file)")
        path = (self.path.parent / value).resolve()
        if not path.is_file():
            raise self.fail_head("map", f"= {value!r}: no such file {path}")
        return path

    def person(self, entry, index: int) -> PersonPlan:
        line = self.person_lines[index] if index < len(self.person_lines) else None
        self.where = f"{self.path}:{line}" if line else str(self.path)
        label = f"person[{index}]"
        if not isinstance(entry, dict):
            raise self.fail(label, "must be a table")
        self.check_keys(entry, label, {"id", "appear", "at", "speed", "exit", "steps", "cart",
                                       "give_way", "yielding", "group", "looks_like",
                                       "heeding"})
        pid = entry.get("id")
        if not isinstance(pid, str) or not pid:
            raise self.fail(f"{label}.id", "is missing (a non-empty string)")
        label = f"person '{pid}'"
        at = self.point(entry.get("at"), f"{label}.at")
        steps_data = entry.get("steps", [])
        if not isinstance(steps_data, list):
            raise self.fail(f"{label}.steps", "must be a list of inline tables")
        steps = tuple(self.step(s, f"{label}.steps[{i}]") for i, s in enumerate(steps_data))
        return PersonPlan(
            id=pid,
            appear=self.number(entry, "appear", f"{label}.appear", 0.0, 86400.0, 0.0),
            at=at,
            speed=self.number(entry, "speed", f"{label}.speed", 0.05, 3.0, 1.0),
            exit=self.point(entry["exit"], f"{label}.exit") if "exit" in entry else at,
            steps=steps, line=line, cart=self.flag(entry, "cart", label),
            give_way=self.flag(entry, "give_way", label) if "give_way" in entry else None,
            yielding=(self.number(entry, "yielding", f"{label}.yielding", 0.0, 1.0)
                      if "yielding" in entry else None),
            group=self.group(entry, label),
            looks_like=self.looks_like(entry, label),
            heeding=self.heeds(entry, label))

    def heeds(self, entry: dict, label: str) -> str | None:
        value = entry.get("heeding")
        if value is not None and value not in ANSWERS:
            raise self.fail(f"{label}.heeding", f"= {value!r} must be one of "
                            f"{', '.join(repr(a) for a in ANSWERS)}")
        return value

    def looks_like(self, entry: dict, label: str) -> str | None:
        value = entry.get("looks_like")
        if value is not None and (not isinstance(value, str) or not value):
            raise self.fail(f"{label}.looks_like", f"= {value!r} must be another person's id")
        return value

    def group(self, entry: dict, label: str) -> str | None:
        value = entry.get("group")
        if value is not None and (not isinstance(value, str) or not value):
            raise self.fail(f"{label}.group", f"= {value!r} must be a group name (a string)")
        return value

    def step(self, entry, label: str) -> Step:
        if not isinstance(entry, dict):
            raise self.fail(label, "must be an inline table such as { pause = 2.0 }")
        kinds = [k for k in entry if k in STEP_KINDS]
        if len(kinds) != 1:
            raise self.fail(label, f"needs exactly one of {', '.join(STEP_KINDS)}; "
                            f"found {', '.join(sorted(entry)) or 'nothing'}")
        kind = kinds[0]
        label = f"{label}.{kind}"
        options = STEP_OPTIONS.get(kind, set())
        extra = set(entry) - {kind} - options
        if extra:
            allowed = ", ".join(sorted(options)) or "none"
            raise self.fail(label, f"unknown option {sorted(extra)[0]!r}; allowed: {allowed}")
        value = entry[kind]
        if kind == "walk":
            return Walk(self.points(value, label), route=self.flag(entry, "route", label))
        if kind == "pause":
            return Pause(self.number(entry, kind, label, 0.0, 86400.0))
        if kind == "approach":
            return Approach(self.number(entry, kind, label, 0.3, 10.0))
        if kind == "answer":
            if (not isinstance(value, list) or not value
                    or not all(isinstance(b, str) and b for b in value)):
                raise self.fail(label, "must be a non-empty list of button labels or typed "
                                "texts (strings)")
            return Answer(tuple(value),
                          delay=self.number(entry, "delay", f"{label}.delay", 0.0, 600.0, 2.0),
                          reach=self.number(entry, "reach", f"{label}.reach", 0.3, 5.0, 1.0),
                          timeout=self.number(entry, "timeout", f"{label}.timeout", 0.0,
                                              86400.0) if "timeout" in entry else math.inf,
                          typing=self.number(entry, "typing", f"{label}.typing", 0.0, 5.0, 0.2))
        if kind == "wait_for_call":
            return WaitForCall(self.number(entry, kind, label, 0.0, 86400.0))
        if kind == "follow":
            return self.follow(entry, label)
        if kind == "make_way":
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                side = entry.get("side")
                if side not in ("left", "right"):
                    raise self.fail(f"{label}.side", f"= {side!r} must be \"left\" or \"right\" "
                                    "(of the robot's heading) when make_way is a distance")
                where = {"aside": self.number(entry, kind, label, 0.1, 5.0), "side": side}
            elif "side" in entry:
                raise self.fail(f"{label}.side", "only goes with a distance: "
                                "make_way = 0.8, side = \"left\"")
            else:
                where = {"to": self.point(value, label)}
            return MakeWay(**where, asked=self.flag(entry, "asked", label, True),
                           near=self.number(entry, "near", f"{label}.near", 0.5, 20.0, 2.0),
                           delay=self.number(entry, "delay", f"{label}.delay", 0.0, 600.0, 1.0),
                           after=self.optional(entry, "after", label, 0.0, 86400.0))
        if kind == "shop":
            return self.shop(entry, label)
        if kind == "sync":
            if not isinstance(value, str) or not value:
                raise self.fail(label, f"= {value!r} must be the id of another person")
            index = entry.get("step", 0)
            if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index <= 10000:
                raise self.fail(f"{label}.step", f"= {index!r} must be a step index 0 .. 10000")
            return Sync(value, index)
        if kind == "lead":
            return Lead(self.points(value, label),
                        dwell=self.number(entry, "dwell", f"{label}.dwell", 0.0, 3600.0, 0.0),
                        after_call=self.flag(entry, "after_call", label),
                        wait_beyond=self.optional(entry, "wait_beyond", label, 0.5, 100.0))
        return Leave(self.point(value, label) if value not in (True, "exit") else None,
                     route=self.flag(entry, "route", label))

    def follow(self, entry: dict, label: str) -> Follow:
        value = entry["follow"]
        distance = 1.2 if value is True else self.number(entry, "follow", label, 0.5, 5.0)
        stop_after = self.optional(entry, "stop_after", label, 0.0, 86400.0)
        stop_after_m = self.optional(entry, "stop_after_m", label, 0.0, 10000.0)
        if "stop_after" in entry and "stop_after_m" in entry:
            raise self.fail(f"{label}.stop_after_m", "give either stop_after (s) or "
                            "stop_after_m (m), not both")
        if "stop_for" in entry and not ("stop_after" in entry or "stop_after_m" in entry):
            raise self.fail(f"{label}.stop_for", "needs stop_after (s) or stop_after_m (m): "
                            "when to stop")
        goal = self.point(entry["goal"], f"{label}.goal") if "goal" in entry else None
        return Follow(distance=distance, after_call=self.flag(entry, "after_call", label),
                      stop_after=stop_after, stop_after_m=stop_after_m,
                      stop_for=self.optional(entry, "stop_for", label, 0.0, 86400.0),
                      lag=self.number(entry, "lag", f"{label}.lag", 0.0, 20.0, 0.0),
                      until=self.optional(entry, "until", label, 0.0, 86400.0),
                      goal=goal,
                      settle=self.number(entry, "settle", f"{label}.settle", 0.0, 600.0, 3.0),
                      timeout=self.optional(entry, "timeout", label, 0.0, 86400.0))

    def shop(self, entry: dict, label: str) -> Shop:
        value = entry["shop"]
        dwell = entry.get("dwell", 5.0)
        if isinstance(dwell, list):
            if (len(dwell) != 2 or not all(_is_number(v) for v in dwell)
                    or not 0.0 <= dwell[0] <= dwell[1] <= 3600.0):
                raise self.fail(f"{label}.dwell", f"= {dwell!r} must be seconds or [low, high] "
                                "with 0 <= low <= high <= 3600")
            dwell = (float(dwell[0]), float(dwell[1]))
        else:
            seconds = self.number(entry, "dwell", f"{label}.dwell", 0.0, 3600.0, 5.0)
            dwell = (seconds, seconds)
        if isinstance(value, str) and value:
            count = entry.get("count", 3)
            if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 1000:
                raise self.fail(f"{label}.count", f"= {count!r} must be a whole number 1 .. 1000")
            return Shop(prefix=value, count=count, dwell=dwell)
        if "count" in entry:
            raise self.fail(f"{label}.count", "only goes with a prefix: shop = \"shelf_\"")
        if not isinstance(value, list) or not value:
            raise self.fail(label, f"= {value!r} must be a list of places or [x, y] points, "
                            "or a place-name prefix such as \"shelf_\"")
        return Shop(places=self.points(value, label), dwell=dwell)

    def check_syncs(self, people: tuple[PersonPlan, ...]) -> None:
        """A sync names another person and one of their steps."""
        plans = {p.id: p for p in people}
        for index, plan in enumerate(people):
            for number, step in enumerate(plan.steps):
                if not isinstance(step, Sync):
                    continue
                line = self.person_lines[index] if index < len(self.person_lines) else None
                self.where = f"{self.path}:{line}" if line else str(self.path)
                label = f"person '{plan.id}'.steps[{number}].sync"
                other = plans.get(step.person)
                if other is None or other is plan:
                    raise self.fail(label, f"= {step.person!r} is not another person; people: "
                                    f"{', '.join(sorted(plans))}")
                if step.step >= max(1, len(other.steps)):
                    raise self.fail(f"{label}.step", f"= {step.step}: '{other.id}' has "
                                    f"{len(other.steps)} steps (0 .. {len(other.steps) - 1})")
        self.where = str(self.path)

    def points(self, value, label: str) -> tuple[Point, ...]:
        if not isinstance(value, list) or not value:
            raise self.fail(label, "must be a non-empty list of places or [x, y] points")
        return tuple(self.point(p, f"{label}[{i}]") for i, p in enumerate(value))

    def flag(self, table: dict, key: str, label: str, default: bool = False) -> bool:
        value = table.get(key, default)
        if not isinstance(value, bool):
            raise self.fail(f"{label}.{key}", f"= {value!r} must be true or false")
        return value

    def optional(self, table: dict, key: str, label: str, low: float, high: float) -> float:
        """A number within [low, high] if the key is there, else infinity (never)."""
        if key not in table:
            return math.inf
        return self.number(table, key, f"{label}.{key}", low, high)

    def check_keys(self, table: dict, label: str, allowed: set[str]) -> None:
        unknown = set(table) - allowed
        if unknown:
            raise self.fail(f"{label}.{sorted(unknown)[0]}",
                            f"unknown field; allowed: {', '.join(sorted(allowed))}")

    def number(self, table: dict, key: str, label: str, low: float, high: float,
               default: float | None = None) -> float:
        value = table.get(key, default)
        if value is None:
            raise self.fail(label, f"is missing (a number {low} .. {high})")
        if (isinstance(value, bool) or not isinstance(value, (int, float))
                or not (low <= value <= high)):
            raise self.fail(label, f"= {value!r} is outside the allowed range {low} .. {high}")
        return float(value)

    def point(self, value, label: str) -> Point:
        if isinstance(value, str) and value:
            return value
        if (isinstance(value, list) and len(value) == 2
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
            return (float(value[0]), float(value[1]))
        raise self.fail(label, f"= {value!r} must be a place name or [x, y] in metres")

    def pose(self, value, label: str) -> Pose:
        if isinstance(value, str) and value:
            return value
        if (isinstance(value, list) and len(value) == 3
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
            return (float(value[0]), float(value[1]), math.radians(value[2]))
        raise self.fail(label, f"= {value!r} must be a place name or [x, y, heading_deg]")


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
