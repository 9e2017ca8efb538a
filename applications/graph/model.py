"""The data model a graph.xml becomes: plain frozen data, separate from the interpreter that runs
it. Two models are equal when their content is; where they were read from does not count.
Transitions of a state are tried by priority (lower number first), unprioritised ones after
them in document order; the checker guarantees that which one fires never depends on that order
unless priorities say so."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..conditions import CompiledCondition
from .location import Location

__all__ = ["Location", "Transition", "State", "Application", "Foreign", "Param"]


@dataclass(frozen=True)
class Foreign:
    """Markup in other XML namespaces (e.g. an SCXML editor's layout data), kept verbatim so a
    round trip through our files does not lose it. Not part of the model's identity."""

    attributes: tuple[tuple[str, str], ...] = ()    # (Clark name "{ns}local", value)
    elements: tuple[str, ...] = ()                  # serialized XML of each foreign child
    namespaces: tuple[tuple[str, str], ...] = ()    # (prefix, uri) declared for them

    def __bool__(self) -> bool:
        return bool(self.attributes or self.elements)


@dataclass(frozen=True)
class Transition:
    target: str
    when: str
    condition: CompiledCondition
    priority: int | None
    location: Location = field(compare=False)
    foreign: Foreign = field(default=Foreign(), compare=False, repr=False)


@dataclass(frozen=True)
class Param:
    """A parameter a state passes to its behavior: a written `value`, or the value of a percept
    (`source`, e.g. answer.office) at the state's entry, optionally looked up in the
    application's database (`lookup` = "table.column", matched on the table's key)."""
    name: str
    value: str | None
    source: str | None = None
    lookup: str | None = None
    location: Location = field(default=None, compare=False)
    value_location: Location = field(default=None, compare=False)


@dataclass(frozen=True)
class State:
    name: str
    behavior: str
    transitions: tuple[Transition, ...]
    final: bool
    location: Location = field(compare=False)
    foreign: Foreign = field(default=Foreign(), compare=False, repr=False)
    params: tuple[Param, ...] = ()

    def __post_init__(self) -> None:
        ranked = sorted((t for t in self.transitions if t.priority is not None),
                        key=lambda t: t.priority)
        ordered = tuple(ranked) + tuple(t for t in self.transitions if t.priority is None)
        object.__setattr__(self, "_ordered", ordered)    # the interpreter asks every tick

    def ordered_transitions(self) -> tuple[Transition, ...]:
        """Prioritised transitions first (lowest number first), then the others in file order."""
        return self._ordered


@dataclass(frozen=True)
class Application:
    name: str
    initial: str
    robot: str | None
    states: dict[str, State]
    folder: Path = field(compare=False)
    graph_file: Path = field(compare=False)
    foreign: Foreign = field(default=Foreign(), compare=False, repr=False)
    params: dict = field(default_factory=dict, compare=False)   # "param.x" -> Constant

    def __hash__(self) -> int:
        return hash((self.name, self.graph_file))

    @property
    def initial_state(self) -> State:
        return self.states[self.initial]
