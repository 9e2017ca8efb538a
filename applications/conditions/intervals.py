"""Solving the constraints a case puts on one numeric percept, exactly, without trying values.

Each literal on a percept x is `x op c` that must hold or fail. Under our semantics a comparison
with an absent x is false, so a literal that must *hold* rules out "absent", and one that must
*fail* allows "absent" or a present value with the opposite comparison. The present values that
remain form one interval (within the declared range) minus a few excluded points.
"""
from __future__ import annotations

import math

from .candidates import ABSENT
from .typed import TIME_IN_STATE, Var

NO_SOLUTION = object()

_OPPOSITE = {"<": ">=", "<=": ">", ">": "<=", ">=": "<", "==": "!=", "!=": "=="}
_MIRRORED = {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "==": "==", "!=": "!="}


def mirrored(op: str) -> str:
    """The operator with its sides swapped: c < x is x > c."""
    return _MIRRORED[op]


class Interval:
    """Present values still possible: lo..hi (each end open or closed), minus `excluded`."""

    __slots__ = ("lo", "lo_closed", "hi", "hi_closed", "excluded", "integer")

    def __init__(self, var: Var) -> None:
        low, high = var.range if var.range is not None else (-math.inf, math.inf)
        self.lo, self.lo_closed = low, True
        self.hi, self.hi_closed = high, True
        self.excluded: set = set()
        self.integer = var.type == "int"

    def restrict(self, op: str, constant: float) -> None:
        if op in ("<", "<="):
            self._upper(constant, op == "<=")
        elif op in (">", ">="):
            self._lower(constant, op == ">=")
        elif op == "==":
            self._upper(constant, True)
            self._lower(constant, True)
        else:
            self.excluded.add(constant)

    def _upper(self, value: float, closed: bool) -> None:
        if value < self.hi or (value == self.hi and not closed):
            self.hi, self.hi_closed = value, closed

    def _lower(self, value: float, closed: bool) -> None:
        if value > self.lo or (value == self.lo and not closed):
            self.lo, self.lo_closed = value, closed

    def contains(self, value: float) -> bool:
        above = value > self.lo or (self.lo_closed and value == self.lo)
        below = value < self.hi or (self.hi_closed and value == self.hi)
        return above and below and value not in self.excluded and \
            (not self.integer or float(value).is_integer())

    def pick(self) -> object:
        """A readable value in the interval, or NO_SOLUTION."""
        for value in self._candidates():
            if self.contains(value):
                return value
        return NO_SOLUTION

    def _candidates(self):
        lo, hi = self.lo, self.hi
        if lo > hi:
            return
        if math.isinf(lo) and math.isinf(hi):
            yield from (0, 1, -1)
        elif math.isinf(hi):
            yield math.floor(lo) + 1
        elif math.isinf(lo):
            yield math.ceil(hi) - 1
        else:
            yield from _simple_between(lo, hi, self.integer)
        for end in (lo, hi):
            if not math.isinf(end):
                yield end
        yield from self._around_exclusions()

    def _around_exclusions(self):
        """Values next to the excluded points, for when a nicer choice was excluded."""
        for point in sorted(self.excluded):
            for step in (1, 0.5, 0.1, 0.01, 0.001):
                yield point + step
                yield point - step


def _simple_between(low: float, high: float, integer: bool):
    if integer or high - low > 2:
        yield math.floor(low) + 1
        yield math.ceil(low)
        return
    middle = (low + high) / 2
    for decimals in range(0, 12):
        rounded = round(middle, decimals)
        if low < rounded < high:
            yield rounded
            break
    yield middle


class Constraint:
    """What one case demands of one numeric percept: may it be absent, and which present
    values remain. Built once per case; two cases' constraints merge by intersection."""

    __slots__ = ("var", "interval", "absent_ok")

    def __init__(self, var: Var, interval: Interval, absent_ok: bool) -> None:
        self.var, self.interval, self.absent_ok = var, interval, absent_ok

    @classmethod
    def of(cls, var: Var, literals) -> "Constraint":
        """From (op, constant, positive) literals with the percept on the left of `op`."""
        interval = Interval(var)
        absent_ok = var.name != TIME_IN_STATE
        for op, constant, positive in literals:
            interval.restrict(op if positive else _OPPOSITE[op], constant)
            absent_ok = absent_ok and not positive
        return cls(var, interval, absent_ok)

    def merge(self, other: "Constraint") -> "Constraint":
        interval = Interval(self.var)
        for source in (self.interval, other.interval):
            interval._lower(source.lo, source.lo_closed)
            interval._upper(source.hi, source.hi_closed)
            interval.excluded |= source.excluded
        return Constraint(self.var, interval, self.absent_ok and other.absent_ok)

    def solve(self) -> object:
        """A value (a number or ABSENT) meeting the constraint, or NO_SOLUTION. A present value
        is preferred, except for a percept without a declared range when absent also works (a
        present value there would leave the answer undecided)."""
        if self.absent_ok and self.var.range is None:
            return ABSENT
        value = self.interval.pick()
        if value is NO_SOLUTION and self.absent_ok:
            return ABSENT
        return value

