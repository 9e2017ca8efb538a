"""Can two conditions be true at the same time? Can one ever be true?

For comparisons of a percept with a constant (the normal case) the answer is exact: the constants
cut each percept's declared range into intervals, and one value per interval and boundary covers
every case, so trying all combinations either finds a *witness* or proves there is none. Where
that argument does not hold — a percept without a declared range, two percepts compared with each
other, too many combinations — the result is `UNDECIDED` with the reason, never a guess.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

from .condition import CompiledCondition
from .typed import TIME_IN_STATE, All, AnyOf, Cmp, Flag, Neg, Typed, Value, Var, variables

OVERLAP = "overlap"            # a witness makes both true
EXCLUSIVE = "exclusive"        # proved: never both true
UNDECIDED = "undecided"        # cannot tell; `reason` says why

MAX_COMBINATIONS = 20_000
ABSENT = None


@dataclass(frozen=True)
class Verdict:
    status: str
    witness: dict[str, object] | None = None   # percept -> value (None = absent)
    reason: str = ""

    def describe_witness(self) -> str:
        return describe(self.witness or {}, self.units)

    units: tuple[tuple[str, str], ...] = ()


def can_both_be_true(first: CompiledCondition, second: CompiledCondition) -> Verdict:
    """OVERLAP with a witness, EXCLUSIVE, or UNDECIDED with a reason."""
    return _search((first, second))


def can_be_true(condition: CompiledCondition) -> Verdict:
    """OVERLAP (satisfiable, with a witness), EXCLUSIVE (never true) or UNDECIDED."""
    return _search((condition,))


def _search(conditions: tuple[CompiledCondition, ...]) -> Verdict:
    found: dict[str, Var] = {}
    for condition in conditions:
        found.update(variables(condition.tree))
    names = sorted(found, key=lambda n: (n == TIME_IN_STATE, n))
    constants = _constants(conditions)
    related = _related_names(conditions)
    domains = [_domain(found[name], constants.get(name, set()) |
                       _borrowed(name, related, constants)) for name in names]
    units = tuple((n, found[n].unit) for n in names if found[n].unit)
    total = math.prod(len(d) for d in domains)
    if total > MAX_COMBINATIONS:
        return Verdict(UNDECIDED, reason=f"too many combinations of {', '.join(names)} to try",
                       units=units)
    for values in itertools.product(*domains):
        assignment = dict(zip(names, values))
        t = assignment.get(TIME_IN_STATE, 0.0)
        if all(c.evaluate(assignment, t) for c in conditions):
            return _witness_verdict(assignment, found, units)
    if related:
        return Verdict(UNDECIDED, reason="two percepts are compared with each other; only "
                       "comparisons with constants can be decided", units=units)
    return Verdict(EXCLUSIVE, units=units)


def _witness_verdict(assignment: dict[str, object], found: dict[str, Var],
                     units: tuple[tuple[str, str], ...]) -> Verdict:
    unbounded = [name for name, value in assignment.items()
                 if value is not ABSENT and found[name].type in ("int", "float")
                 and found[name].range is None]
    if unbounded:
        return Verdict(UNDECIDED, assignment,
                       f"{', '.join(unbounded)} declare{'s' if len(unbounded) == 1 else ''} no "
                       "range, so whether the values that make both true can occur is unknown",
                       units)
    return Verdict(OVERLAP, assignment, units=units)


def _constants(conditions: tuple[CompiledCondition, ...]) -> dict[str, set]:
    found: dict[str, set] = {}
    for condition in conditions:
        _walk_constants(condition.tree, found)
    return found


def _walk_constants(tree: Typed, found: dict[str, set]) -> None:
    if isinstance(tree, Cmp):
        left, right = tree.left, tree.right
        if isinstance(left, Var) and isinstance(right, Value):
            found.setdefault(left.name, set()).add(right.value)
        elif isinstance(right, Var) and isinstance(left, Value):
            found.setdefault(right.name, set()).add(left.value)
    elif isinstance(tree, Neg):
        _walk_constants(tree.item, found)
    elif isinstance(tree, (All, AnyOf)):
        for item in tree.items:
            _walk_constants(item, found)


def _related_names(conditions: tuple[CompiledCondition, ...]) -> dict[str, set[str]]:
    related: dict[str, set[str]] = {}

    def walk(tree: Typed) -> None:
        if isinstance(tree, Cmp) and isinstance(tree.left, Var) and isinstance(tree.right, Var):
            related.setdefault(tree.left.name, set()).add(tree.right.name)
            related.setdefault(tree.right.name, set()).add(tree.left.name)
        elif isinstance(tree, Neg):
            walk(tree.item)
        elif isinstance(tree, (All, AnyOf)):
            for item in tree.items:
                walk(item)
    for condition in conditions:
        walk(condition.tree)
    return related


def _borrowed(name: str, related: dict[str, set[str]], constants: dict[str, set]) -> set:
    borrowed: set = set()
    for other in related.get(name, ()):
        borrowed |= constants.get(other, set())
    return borrowed


def _domain(var: Var, constants: set) -> list:
    """Candidate values: present values first (nicer witnesses), absent last."""
    if var.type == "bool":
        values: list = [True, False]
    elif var.type == "str":
        values = sorted(c for c in constants if isinstance(c, str)) + [_other_string(constants)]
    else:
        values = _numbers(var, {c for c in constants if isinstance(c, (int, float))
                                and not isinstance(c, bool)})
    if var.name != TIME_IN_STATE:
        values.append(ABSENT)
    return values


def _other_string(constants: set) -> str:
    candidate = "something else"
    while candidate in constants:
        candidate += "!"
    return candidate


def _numbers(var: Var, constants: set) -> list:
    """Interior values of each interval first (they make readable witnesses), then the
    constants themselves, then the ends of the range."""
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
    exact = [p for p in points if p not in ends and (not integer or float(p).is_integer())]
    bounds = [p for p in points if p in ends and (not integer or float(p).is_integer())]
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


def describe(witness: dict[str, object], units: tuple[tuple[str, str], ...] = ()) -> str:
    """`user.distance = 0.5 m, time_in_state = 16 s` — a witness as a person reads it."""
    unit_of = dict(units)
    parts = []
    for name, value in witness.items():
        parts.append(_describe_value(name, value, unit_of.get(name)))
    return ", ".join(parts)


def _describe_value(name: str, value: object, unit: str | None) -> str:
    if value is ABSENT:
        return f"{name} absent"
    if isinstance(value, bool):
        return f"{name} = {'true' if value else 'false'}"
    if isinstance(value, str):
        return f'{name} = "{value}"'
    number = f"{value:g}"
    return f"{name} = {number} {unit}" if unit else f"{name} = {number}"
