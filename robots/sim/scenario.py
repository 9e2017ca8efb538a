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
from robots.tomlfile import read_toml

Point = Union[str, tuple[float, float]]          # a place name or (x, y) in metres
Pose = Union[str, tuple[float, float, float]]    # a place name or (x, y, heading rad)


@dataclass(frozen=True)
class Walk:
    waypoints: tuple[Point, ...]


@dataclass(frozen=True)
class Pause:
    seconds: float


@dataclass(frozen=True)
class Approach:
    distance: float               # m, centre to centre, where the person stops


@dataclass(frozen=True)
class Answer:
    buttons: tuple[str, ...]      # one per prompt, in order
    delay: float = 2.0            # s after the prompt appears
    reach: float = 1.0            # m; farther away the person first steps closer
    timeout: float = math.inf     # s; give up and go on with the next step


@dataclass(frozen=True)
class WaitForCall:
    timeout: float                # s; without an utterance by then the person leaves


@dataclass(frozen=True)
class Leave:
    to: Point | None = None       # None: the person's exit


Step = Union[Walk, Pause, Approach, Answer, WaitForCall, Leave]
STEP_KINDS = ("walk", "pause", "approach", "answer", "wait_for_call", "leave")


@dataclass(frozen=True)
class PersonPlan:
    id: str
    appear: float                 # s of sim time
    at: Point
    speed: float                  # m/s
    exit: Point
    steps: tuple[Step, ...]
    line: int | None = None       # of the [[person]] header, for messages


@dataclass(frozen=True)
class Scenario:
    name: str
    description: str
    duration: float
    robot: Pose
    people: tuple[PersonPlan, ...]
    source: Path | None = None

    def where(self, person_index: int | None = None) -> str:
        """'file:line' of the scenario or of one person's header, for messages."""
        place = str(self.source or "<scenario>")
        if person_index is not None and self.people[person_index].line:
            place += f":{self.people[person_index].line}"
        return place


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file; a ScenarioError names the file, line and field."""
    path = Path(path)
    data, text = read_toml(path, ScenarioError, "scenario file")
    return parse_scenario(data, path, _person_lines(text))


def parse_scenario(data: dict, path: Path | str = "<scenario>",
                   person_lines: list[int] | None = None) -> Scenario:
    """Build a Scenario from parsed TOML; `path` and `person_lines` only label errors."""
    reader = _Reader(Path(path), person_lines or [])
    return reader.scenario(data)


def _person_lines(text: str) -> list[int]:
    """Line numbers (1-based) of the `[[person]]` headers, in order."""
    return [number for number, line in enumerate(text.splitlines(), 1)
            if re.match(r"\s*\[\[\s*person\s*\]\]", line)]


class _Reader:
    """Checks each field, naming file, line and field on the first error."""

    def __init__(self, path: Path, person_lines: list[int]) -> None:
        self.path = path
        self.person_lines = person_lines
        self.where = str(path)

    def fail(self, field_name: str, why: str) -> ScenarioError:
        return ScenarioError(f"{self.where}: {field_name}: {why}")

    def scenario(self, data: dict) -> Scenario:
        unknown = set(data) - {"scenario", "person"}
        if unknown:
            raise self.fail(sorted(unknown)[0], "unknown table; allowed: [scenario], [[person]]")
        head = data.get("scenario", {})
        if not isinstance(head, dict):
            raise self.fail("scenario", "must be a table")
        self.check_keys(head, "scenario", {"name", "description", "duration", "robot"})
        duration = self.number(head, "duration", "scenario.duration", 1.0, 86400.0, 120.0)
        robot = self.pose(head.get("robot", "robot_home"), "scenario.robot")
        people_data = data.get("person", [])
        if not isinstance(people_data, list):
            raise self.fail("person", "must be an array of tables: [[person]]")
        people = tuple(self.person(entry, index) for index, entry in enumerate(people_data))
        self.where = str(self.path)
        ids = [p.id for p in people]
        for pid in ids:
            if ids.count(pid) > 1:
                raise self.fail("person.id", f"'{pid}' is used twice; ids must be unique")
        return Scenario(name=str(head.get("name", self.path.stem)),
                        description=str(head.get("description", "")),
                        duration=duration, robot=robot, people=people, source=self.path)

    def person(self, entry, index: int) -> PersonPlan:
        line = self.person_lines[index] if index < len(self.person_lines) else None
        self.where = f"{self.path}:{line}" if line else str(self.path)
        label = f"person[{index}]"
        if not isinstance(entry, dict):
            raise self.fail(label, "must be a table")
        self.check_keys(entry, label, {"id", "appear", "at", "speed", "exit", "steps"})
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
            steps=steps, line=line)

    def step(self, entry, label: str) -> Step:
        if not isinstance(entry, dict):
            raise self.fail(label, "must be an inline table such as { pause = 2.0 }")
        kinds = [k for k in entry if k in STEP_KINDS]
        if len(kinds) != 1:
            raise self.fail(label, f"needs exactly one of {', '.join(STEP_KINDS)}; "
                            f"found {', '.join(sorted(entry)) or 'nothing'}")
        kind = kinds[0]
        label = f"{label}.{kind}"
        options = {"answer": {"delay", "reach", "timeout"}}.get(kind, set())
        extra = set(entry) - {kind} - options
        if extra:
            allowed = ", ".join(sorted(options)) or "none"
            raise self.fail(label, f"unknown option {sorted(extra)[0]!r}; allowed: {allowed}")
        value = entry[kind]
        if kind == "walk":
            if not isinstance(value, list) or not value:
                raise self.fail(label, "must be a non-empty list of places or [x, y] points")
            return Walk(tuple(self.point(p, f"{label}[{i}]") for i, p in enumerate(value)))
        if kind == "pause":
            return Pause(self.number(entry, kind, label, 0.0, 86400.0))
        if kind == "approach":
            return Approach(self.number(entry, kind, label, 0.3, 10.0))
        if kind == "answer":
            if (not isinstance(value, list) or not value
                    or not all(isinstance(b, str) and b for b in value)):
                raise self.fail(label, "must be a non-empty list of button labels (strings)")
            return Answer(tuple(value),
                          delay=self.number(entry, "delay", f"{label}.delay", 0.0, 600.0, 2.0),
                          reach=self.number(entry, "reach", f"{label}.reach", 0.3, 5.0, 1.0),
                          timeout=self.number(entry, "timeout", f"{label}.timeout", 0.0,
                                              86400.0) if "timeout" in entry else math.inf)
        if kind == "wait_for_call":
            return WaitForCall(self.number(entry, kind, label, 0.0, 86400.0))
        return Leave(self.point(value, label) if value not in (True, "exit") else None)

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
