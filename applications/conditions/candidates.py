"""Candidate values of one percept: few enough to try, yet one per case that matters.

A string percept that declares its values (an answer with offered choices) takes only those.

The constants a percept is compared with cut its declared range into intervals; every value
inside one interval compares the same way with every constant. So the constants themselves, one
value inside each interval, the ends of the range and *absent* cover all cases exactly.
"""
from __future__ import annotations

import math

from .typed import TIME_IN_STATE, Var

ABSENT = None


def domain(var: Var, constants: set) -> list:
    """Candidates for `var`, readable ones first (they become witnesses), absent last."""
    if var.type == "bool":
        values: list = [True, False]
    elif var.type == "str" and var.values is not None:
        values = _known_strings(var.values, constants)
    elif var.type == "str":
        values = sorted(c for c in constants if isinstance(c, str)) + [_other_string(constants)]
    else:
        values = _numbers(var, {c for c in constants
                                if isinstance(c, (int, float)) and not isinstance(c, bool)})
    if var.name != TIME_IN_STATE:
        values.append(ABSENT)
    return values


def _known_strings(possible: tuple[str, ...], constants: set) -> list:
    """A string percept with a finite set of values: those the conditions name, and one of the
    others (all others compare alike with every constant); names outside the set cannot occur."""
    named = [value for value in possible if value in constants]
    others = [value for value in possible if value not in constants]
    return named + others[:1]


def _other_string(constants: set) -> str:
    candidate = "something else"
    while candidate in constants:
        candidate += "!"
    return candidate


def _numbers(var: Var, constants: set) -> list:
    """Interior values of each interval first, then the constants, then the range's ends."""
    integer = var.type == "int"
    if var.range is not None:
        low, high = var.range
        points = sorted({p for p in constants if low <= p <= high} | {low, high})
        ends = {low, high}
    else:
        points = sorted(constants) or [0.0]
        points = [points[0] - 1.0, *points, points[-1] + 1.0]
        ends = set()
    interior = [_inside(a, b, integer) for a, b in zip(points, points[1:])]
    whole = [p for p in points if not integer or float(p).is_integer()]
    exact = [p for p in whole if p not in ends]
    bounds = [p for p in whole if p in ends]
    return list(dict.fromkeys(v for v in interior + exact + bounds if v is not None))


def _inside(low: float, high: float, integer: bool) -> float | None:
    """The simplest value strictly between low and high (an integer for integer percepts)."""
    if integer or high - low > 2:
        value = math.floor(low) + 1
        return value if value < high else None
    middle = (low + high) / 2
    for decimals in range(0, 12):
        rounded = round(middle, decimals)
        if low < rounded < high:
            return rounded
    return middle if low < middle < high else None
