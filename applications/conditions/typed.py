"""The type-checked form of a condition: names resolved to their declarations, literal numbers
converted to the unit of the percept they are compared with. Compiler and analyser read this."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Union

TIME_IN_STATE = "time_in_state"


@dataclass(frozen=True)
class Var:
    name: str
    type: str                              # "bool", "int", "float", "str"
    unit: str | None
    range: tuple[float, float] | None
    values: tuple[str, ...] | None = None  # a string percept's possible values; None = any


@dataclass(frozen=True)
class Value:
    value: object                          # in the unit of the Var it is compared with


Term = Union[Var, Value]


@dataclass(frozen=True)
class Const:
    value: bool


@dataclass(frozen=True)
class Flag:
    var: Var                               # a bool percept read as a condition


@dataclass(frozen=True)
class Cmp:
    op: str
    left: Term
    right: Term


@dataclass(frozen=True)
class Neg:
    item: "Typed"


@dataclass(frozen=True)
class All:
    items: tuple["Typed", ...]


@dataclass(frozen=True)
class AnyOf:
    items: tuple["Typed", ...]


Typed = Union[Const, Flag, Cmp, Neg, All, AnyOf]


def variables(tree: Typed) -> dict[str, Var]:
    """Every percept (and time_in_state) the condition reads, by name."""
    found: dict[str, Var] = {}
    _collect(tree, found)
    return found


def _collect(tree: Typed, found: dict[str, Var]) -> None:
    if isinstance(tree, Flag):
        found[tree.var.name] = tree.var
    elif isinstance(tree, Cmp):
        for term in (tree.left, tree.right):
            if isinstance(term, Var):
                found[term.name] = term
    elif isinstance(tree, Neg):
        _collect(tree.item, found)
    elif isinstance(tree, (All, AnyOf)):
        for item in tree.items:
            _collect(item, found)
