"""The percepts and skill-status names that application conditions may read, with type, unit and range.

L3 never reads the blackboard: it reads a `PerceptView`, a read-only mapping from these names to
values, built by L2 each tick. The declarations let the application checker reject an unknown
name, a type mismatch or a unit mismatch before the robot moves. A value of `None` means
*absent* (no user, stale data): a comparison with an absent value is false.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Iterator


@dataclass(frozen=True)
class PerceptSpec:
    name: str
    type: str                                  # "bool", "int", "float" or "str"
    unit: str | None = None                    # "m", "s", "rad" or None for a plain number
    range: tuple[float, float] | None = None   # inclusive; None when unbounded or unknown
    doc: str = ""


def _spec(name: str, type_: str, unit: str | None = None,
          range_: tuple[float, float] | None = None, doc: str = "") -> PerceptSpec:
    return PerceptSpec(name, type_, unit, range_, doc)


PERCEPTS: dict[str, PerceptSpec] = {spec.name: spec for spec in (
    _spec("people.count", "int", None, (0, 1000), "people tracked around the robot now"),
    _spec("people.new", "int", None, (0, 1000),
          "people tracked now whose track was confirmed after the active macro-behavior started, "
          "i.e. since the current state was entered"),
    _spec("user.present", "bool", doc="an interaction partner is selected among the tracked people"),
    _spec("user.distance", "float", "m", (0.0, 30.0),
          "distance from the robot's centre to the user; absent when there is no user"),
    _spec("user.approaching", "bool", doc="the user's speed towards the robot exceeds 0.1 m/s"),
    _spec("user.left", "bool",
          doc="the user selected during the active macro-behavior is no longer tracked"),
    _spec("survey.done", "bool", doc="every survey question has an answer"),
    _spec("survey.answered", "int", None, (0, 1000), "survey questions answered so far"),
    _spec("speech.busy", "bool", doc="the robot is still speaking"),
    _spec("motion.failed", "bool", doc="the motion skill reported failure"),
    _spec("robot.fault", "bool", doc="the base reported a fault (link down, stale sensors, stall)"),
)}

TIME_IN_STATE = PerceptSpec("time_in_state", "float", "s", (0.0, 1e9),
                            "seconds since the current state was entered (provided by L3)")


class PerceptView(Mapping[str, Any]):
    """A read-only snapshot of percept values for one tick."""

    __slots__ = ("_values", "t")

    def __init__(self, values: dict[str, Any], t: float) -> None:
        self._values = dict(values)
        self.t = t

    def __getitem__(self, name: str) -> Any:
        return self._values[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __repr__(self) -> str:
        return f"PerceptView(t={self.t:.2f}, {self._values!r})"
