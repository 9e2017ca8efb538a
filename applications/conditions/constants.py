"""Application parameters a condition reads by name (`time_in_state > param.idle_timeout`).

A parameter is written once, under `<application>` in graph.xml (`<param name="idle_timeout"
value="30s"/>`), and is fixed for a run. So a condition reads it as if the value had been written
in its place, in the unit it was written in: the type checker converts it to the percept's unit
exactly, folds it, and the analyser proves exclusivity with it, as with any written number.
"""
from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

from .hints import unit_alias
from .nodes import And, Compare, Literal, Name, Node, Not, Or
from .units import UNITS, NumberError, decimal_text, exact

PREFIX = "param."
SPEEDS = ("m/s", "cm/s", "km/h")          # units a behavior's speed is written in
_NUMBER = re.compile(r"\s*(-?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)\s*([A-Za-zµ/]*)\s*")


class ConstantError(ValueError):
    """A parameter value a condition cannot read; the message says what to write."""


@dataclass(frozen=True)
class Constant:
    """A named value fixed for the run. Declared like a percept (`type`, `unit`) so listings
    and did-you-mean hints find it, but read as the value written."""
    name: str                   # "param.idle_timeout"
    text: str                   # as written: "30s"
    value: object               # Fraction, str or bool
    unit: str | None            # a condition unit (s, m, deg…), a speed unit, or None
    location: Any = None

    @property
    def type(self) -> str:
        if isinstance(self.value, bool):
            return "bool"
        return "str" if isinstance(self.value, str) else "float"

    range = None
    values = None

    @property
    def doc(self) -> str:
        return f"application parameter, {self.text}"

    @property
    def provider(self) -> str:
        return "graph.xml"


def parse_constant(name: str, text: str, location: Any = None) -> Constant:
    """The parameter `name` (without "param.") written as `text`: true/false, a number with an
    optional unit, or else a text. ConstantError for a unit the language does not know."""
    stripped = text.strip()
    full = PREFIX + name
    if stripped in ("true", "false"):
        return Constant(full, stripped, stripped == "true", None, location)
    match = _NUMBER.fullmatch(text)
    if match is None:
        return Constant(full, stripped, stripped, None, location)
    number, unit = match.groups()
    try:
        value = exact(number)
    except NumberError as problem:
        raise ConstantError(str(problem)) from None
    if not unit:
        return Constant(full, stripped, value, None, location)
    if unit in UNITS or unit in SPEEDS:
        return Constant(full, stripped, value, unit, location)
    alias = unit_alias(unit)
    if alias is not None:
        written = value * alias[1]
        raise ConstantError(f"unit '{unit}' is written {alias[0]}: write "
                            f"value=\"{decimal_text(written)}{alias[0]}\"")
    raise ConstantError(f"unknown unit '{unit}'; units: {', '.join([*UNITS, *SPEEDS])}")


def substitute(node: Node, declarations: Mapping[str, Any]) -> tuple[Node, dict[int, Constant]]:
    """`node` with each name of a declared Constant replaced by its value (same offsets), and
    the constants replaced, by the offset where their name was written."""
    used: dict[int, Constant] = {}
    return _replace(node, declarations, used), used


def _replace(node: Node, declarations: Mapping[str, Any], used: dict[int, Constant]) -> Node:
    if isinstance(node, Name):
        found = declarations.get(node.name)
        if not isinstance(found, Constant):
            return node
        used[node.offset] = found
        return Literal(found.value, found.unit, node.offset, node.end)
    if isinstance(node, Compare):
        return replace(node, left=_replace(node.left, declarations, used),
                       right=_replace(node.right, declarations, used))
    if isinstance(node, Not):
        return replace(node, operand=_replace(node.operand, declarations, used))
    if isinstance(node, (And, Or)):
        return replace(node, operands=tuple(_replace(item, declarations, used)
                                            for item in node.operands))
    return node


def speed_problem(constant: Constant) -> str | None:
    """Conditions compare no speeds: the reason, for a speed parameter read in a condition."""
    if constant.unit in SPEEDS:
        return (f"'{constant.name}' is a speed ({constant.text}); no percept is a speed, so a "
                "condition cannot compare it: pass it to a behavior's speed parameter instead")
    return None


def unknown_parameter(name: str, declarations: Mapping[str, Any]) -> str:
    """The message for `param.x` that no `<param>` under `<application>` declares."""
    from ..graph.diagnostics import did_you_mean
    known = sorted(n for n, d in declarations.items() if isinstance(d, Constant))
    close = did_you_mean(name, known)
    listed = f"; the parameters: {', '.join(known)}" if known else ""
    return (f"unknown parameter '{name}'{close}{listed}; declare it in graph.xml inside "
            f"<application>: <param name=\"{name[len(PREFIX):]}\" value=\"30s\"/>")
