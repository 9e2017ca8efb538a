"""Can two conditions be true at the same time? Can one ever be true?

Each condition is put in disjunctive normal form once: a list of *cases*, each a conjunction of
literals (a comparison or a flag, possibly negated). Two conditions overlap exactly when some
case of one and some case of the other can hold together. A literal comparing a percept with a
constant constrains that percept alone, so a pair of cases is solved percept by percept: numeric
percepts by intersecting intervals (intervals.py), true/false and string percepts by trying
their few candidate values (candidates.py). That is exact, and fast.

The answer is OVERLAP with a concrete *witness*, EXCLUSIVE (proved), or UNDECIDED with the
reason: a witness that needs a value of a percept without a declared range, two percepts
compared with each other and no witness found, or too many cases. The checker never guesses.
"""
from __future__ import annotations

import itertools
import operator
from dataclasses import dataclass
from functools import cached_property, lru_cache

from .candidates import ABSENT, domain
from .condition import CompiledCondition
from .intervals import NO_SOLUTION, Constraint, mirrored
from .typed import TIME_IN_STATE, All, AnyOf, Cmp, Const, Flag, Neg, Typed, Value, Var

OVERLAP = "overlap"            # a witness makes both true
EXCLUSIVE = "exclusive"        # proved: never both true
UNDECIDED = "undecided"        # cannot tell; `reason` says why

MAX_CASES = 256                # per condition, after distributing and/or
MAX_COMBINATIONS = 20_000      # per group of percepts compared with each other
NUMERIC = ("int", "float")

_OPS = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge,
        "==": operator.eq, "!=": operator.ne}


@dataclass(frozen=True)
class Verdict:
    status: str
    witness: dict[str, object] | None = None   # percept -> value (None = absent)
    reason: str = ""
    units: tuple[tuple[str, str], ...] = ()

    def describe_witness(self) -> str:
        return describe(self.witness or {}, self.units)


def can_both_be_true(first: CompiledCondition, second: CompiledCondition) -> Verdict:
    """OVERLAP with a witness, EXCLUSIVE, or UNDECIDED with a reason."""
    return _search((_prepared(first), _prepared(second)))


def can_be_true(condition: CompiledCondition) -> Verdict:
    """OVERLAP (satisfiable, with a witness), EXCLUSIVE (never true) or UNDECIDED."""
    return _search((_prepared(condition),))


# ---------------------------------------------------------------- literals and cases

class Literal:
    """An atom (a flag or a comparison) that must hold (`positive`) or fail."""

    __slots__ = ("atom", "positive", "names", "bound")

    def __init__(self, atom: Typed, positive: bool) -> None:
        self.atom = atom
        self.positive = positive
        self.names = _names(atom)
        self.bound = _bound(atom, positive)     # (op, constant, positive) for numeric x op c

    def holds(self, values: dict) -> bool:
        return _holds(self.atom, values) == self.positive


class Case:
    """One conjunction of literals, sorted by how it is solved: numeric percepts compared with
    constants become interval constraints, other single-percept literals are kept per percept,
    literals comparing two percepts are kept apart."""

    __slots__ = ("numeric", "others", "linked")

    def __init__(self, literals: tuple[Literal, ...]) -> None:
        bounds: dict[str, list] = {}
        variables: dict[str, Var] = {}
        self.others: dict[str, tuple[Literal, ...]] = {}
        self.linked: tuple[Literal, ...] = tuple(l for l in literals if len(l.names) > 1)
        for literal in literals:
            if len(literal.names) != 1:
                continue
            if literal.bound is not None:
                bounds.setdefault(literal.names[0], []).append(literal.bound)
                variables[literal.names[0]] = _var_of(literal.atom)
            else:
                name = literal.names[0]
                self.others[name] = self.others.get(name, ()) + (literal,)
        self.numeric = {name: Constraint.of(variables[name], found)
                        for name, found in bounds.items()}


class _TooManyCases(Exception):
    pass


def cases(tree: Typed) -> tuple[tuple[Literal, ...], ...] | None:
    """The condition as an 'or' of 'and's of literals; None when that would be too large."""
    try:
        return tuple(_dnf(tree, True))
    except _TooManyCases:
        return None


def _dnf(tree: Typed, positive: bool) -> list[tuple[Literal, ...]]:
    if isinstance(tree, Const):
        return [()] if tree.value == positive else []
    if isinstance(tree, (Flag, Cmp)):
        return [(Literal(tree, positive),)]
    if isinstance(tree, Neg):
        return _dnf(tree.item, not positive)
    conjunction = isinstance(tree, All) == positive
    parts = [_dnf(item, positive) for item in tree.items]
    if not conjunction:
        combined = [case for part in parts for case in part]
    else:
        combined = [()]
        for part in parts:
            combined = [left + right for left in combined for right in part]
            if len(combined) > MAX_CASES:
                raise _TooManyCases
    if len(combined) > MAX_CASES:
        raise _TooManyCases
    return combined


@dataclass(frozen=True)
class _Prepared:
    """What the analysis needs of one condition, computed once per condition."""
    cases: tuple[Case, ...] | None
    variables: dict
    constants: dict
    related: dict


def _prepared(condition: CompiledCondition) -> _Prepared:
    prepared = condition.derived.get("analysis")
    if prepared is None:
        variables: dict[str, Var] = {}
        constants: dict[str, set] = {}
        related: dict[str, set[str]] = {}
        _gather(condition.tree, variables, constants, related)
        normal = cases(condition.tree)
        prepared = condition.derived["analysis"] = _Prepared(
            None if normal is None else tuple(Case(literals) for literals in normal),
            variables, constants, related)
    return prepared


# ---------------------------------------------------------------- search

class _Percepts:
    """The percepts of the conditions under analysis; merged, and candidate values computed,
    only when a search needs them (most exclusive pairs never do)."""

    def __init__(self, conditions: tuple[_Prepared, ...]) -> None:
        self.conditions = conditions

    @cached_property
    def variables(self) -> dict[str, Var]:
        merged: dict[str, Var] = {}
        for condition in self.conditions:
            merged.update(condition.variables)
        return merged

    @cached_property
    def order(self) -> list[str]:
        return sorted(self.variables, key=lambda n: (n == TIME_IN_STATE, n))

    @cached_property
    def constants(self) -> dict[str, set]:
        """Constants each percept is compared with, including those of percepts it is
        compared with (so candidates cover both sides)."""
        constants: dict[str, set] = {}
        related: dict[str, set[str]] = {}
        for condition in self.conditions:
            for name, values in condition.constants.items():
                constants.setdefault(name, set()).update(values)
            for name, others in condition.related.items():
                related.setdefault(name, set()).update(others)
        for name, others in related.items():
            for other in others:
                constants.setdefault(name, set()).update(constants.get(other, set()))
        return constants

    def candidates(self, name: str, var: Var | None = None) -> list:
        if var is not None and var.type == "bool":
            return _BOOL_CANDIDATES
        return _domain(self.variables[name], frozenset(self.constants.get(name, ())))

    @property
    def units(self) -> tuple[tuple[str, str], ...]:
        return tuple((n, self.variables[n].unit) for n in self.order if self.variables[n].unit)


_BOOL_CANDIDATES = [True, False, ABSENT]


@lru_cache(maxsize=8192)
def _domain(var: Var, constants: frozenset) -> list:
    return domain(var, set(constants))


def _search(conditions: tuple[_Prepared, ...]) -> Verdict:
    if any(condition.cases is None for condition in conditions):
        return Verdict(UNDECIDED, reason=f"a condition has more than {MAX_CASES} cases once "
                       "its and/or are distributed; simplify it")
    percepts = _Percepts(conditions)
    found: list[Verdict] = []
    inexact = False
    for combination in itertools.product(*(condition.cases for condition in conditions)):
        solution, exact = _solve(combination, percepts)
        inexact = inexact or not exact
        if solution is not None:
            found.append(_verdict(solution, percepts))
    definite = [verdict for verdict in found if verdict.status == OVERLAP]
    if definite:
        return min(definite, key=_plausibility)
    if found:
        return found[0]
    if inexact:
        return Verdict(UNDECIDED, reason="two percepts are compared with each other (or too "
                       "many combinations); only comparisons with constants can be decided",
                       units=percepts.units)
    return Verdict(EXCLUSIVE, units=percepts.units)


def _plausibility(verdict: Verdict) -> tuple[int, int]:
    """Prefer witnesses where things are present and true: they read like real situations."""
    negative = sum(1 for value in verdict.witness.values() if value is ABSENT or value is False)
    return negative, len(verdict.witness)


def _solve(combination: tuple[Case, ...], percepts: _Percepts) -> tuple[dict | None, bool]:
    """Values making every literal of the cases hold (None when there are none), and whether
    that answer is exact."""
    if any(case.linked for case in combination):
        literals = [literal for case in combination for literal in _all_literals(case)]
        return _solve_linked(literals, percepts)
    numeric: dict[str, Constraint] = {}
    others: dict[str, tuple[Literal, ...]] = {}
    for case in combination:
        for name, constraint in case.numeric.items():
            numeric[name] = numeric[name].merge(constraint) if name in numeric else constraint
        for name, literals in case.others.items():
            others[name] = others.get(name, ()) + literals
    solution: dict[str, object] = {}
    for name, constraint in numeric.items():
        value = constraint.solve()
        if value is NO_SOLUTION:
            return None, True
        solution[name] = value
    for name, literals in others.items():
        if name in numeric:     # a numeric percept also compared with == true/strings
            return _solve_linked([l for case in combination for l in _all_literals(case)],
                                 percepts)
        value = _first_value(percepts.candidates(name, _var_of(literals[0].atom)), literals)
        if value is NO_SOLUTION:
            return None, True
        solution[name] = value
    return solution, True


def _all_literals(case: Case) -> list[Literal]:
    """Every literal of a case, numeric ones rebuilt as plain literals for brute force."""
    literals = list(case.linked)
    for group in case.others.values():
        literals.extend(group)
    for name, constraint in case.numeric.items():
        literals.append(_ConstraintLiteral(name, constraint))
    return literals


class _ConstraintLiteral:
    """A numeric constraint posing as a literal, for the brute-force search."""

    def __init__(self, name: str, constraint: Constraint) -> None:
        self.names = (name,)
        self.constraint = constraint

    def holds(self, values: dict) -> bool:
        value = values[self.names[0]]
        if value is ABSENT:
            return self.constraint.absent_ok
        return self.constraint.interval.contains(value)


def _first_value(candidates: list, literals: tuple[Literal, ...]) -> object:
    for value in candidates:
        values = {literals[0].names[0]: value}
        if all(literal.holds(values) for literal in literals):
            return value
    return NO_SOLUTION


def _solve_linked(literals: list, percepts: _Percepts) -> tuple[dict | None, bool]:
    """Try candidate values together for percepts compared with each other. A witness found
    is real; finding none proves nothing (the answer is then not exact)."""
    solution: dict[str, object] = {}
    for names, group in _groups(literals):
        choices = [percepts.candidates(name) for name in names]
        total = 1
        for values in choices:
            total *= len(values)
        if total > MAX_COMBINATIONS:
            return None, False
        found = next((assignment for values in itertools.product(*choices)
                      if all(literal.holds(assignment := dict(zip(names, values)))
                             for literal in group)), None)
        if found is None:
            return None, len(names) == 1
        solution.update(found)
    return solution, True


def _groups(literals: list) -> list[tuple[tuple[str, ...], list]]:
    """Literals grouped by the percepts they read; linked percepts share a group."""
    parent: dict[str, str] = {}

    def root(name: str) -> str:
        while parent.setdefault(name, name) != name:
            name = parent[name]
        return name

    for literal in literals:
        for name in literal.names[1:]:
            parent[root(name)] = root(literal.names[0])
    grouped: dict[str, tuple[set, list]] = {}
    for literal in literals:
        entry = grouped.setdefault(root(literal.names[0]), (set(), []))
        entry[0].update(literal.names)
        entry[1].append(literal)
    return [(tuple(sorted(names)), group) for names, group in grouped.values()]


def _verdict(solution: dict, percepts: _Percepts) -> Verdict:
    witness = {name: solution[name] for name in percepts.order if name in solution}
    unbounded = [name for name, value in witness.items()
                 if value is not ABSENT and percepts.variables[name].type in NUMERIC
                 and percepts.variables[name].range is None]
    if unbounded:
        plural = "s" if len(unbounded) == 1 else ""
        return Verdict(UNDECIDED, witness,
                       f"{', '.join(unbounded)} declare{plural} no range, so whether such "
                       "values can occur is unknown", percepts.units)
    return Verdict(OVERLAP, witness, units=percepts.units)


# ---------------------------------------------------------------- atoms

def _gather(tree: Typed, variables: dict, constants: dict, related: dict) -> None:
    if isinstance(tree, Flag):
        variables[tree.var.name] = tree.var
    elif isinstance(tree, Cmp):
        for term, other in ((tree.left, tree.right), (tree.right, tree.left)):
            if isinstance(term, Var):
                variables[term.name] = term
                if isinstance(other, Value):
                    constants.setdefault(term.name, set()).add(other.value)
                else:
                    related.setdefault(term.name, set()).add(other.name)
    elif isinstance(tree, Neg):
        _gather(tree.item, variables, constants, related)
    elif isinstance(tree, (All, AnyOf)):
        for item in tree.items:
            _gather(item, variables, constants, related)


def _names(atom: Typed) -> tuple[str, ...]:
    if isinstance(atom, Flag):
        return (atom.var.name,)
    left, right = atom.left, atom.right
    if isinstance(left, Var):
        if isinstance(right, Var) and right.name != left.name:
            return (left.name, right.name)
        return (left.name,)
    return (right.name,)


def _var_of(atom: Typed) -> Var:
    if isinstance(atom, Flag):
        return atom.var
    return atom.left if isinstance(atom.left, Var) else atom.right


def _bound(atom: Typed, positive: bool) -> tuple[str, float, bool] | None:
    if not isinstance(atom, Cmp):
        return None
    left, right = atom.left, atom.right
    if isinstance(left, Var) and isinstance(right, Value) and left.type in NUMERIC:
        return atom.op, right.value, positive
    if isinstance(right, Var) and isinstance(left, Value) and right.type in NUMERIC:
        return mirrored(atom.op), left.value, positive
    return None


def _holds(atom: Typed, values: dict) -> bool:
    """The atom's truth under our semantics: absent values make comparisons false."""
    if isinstance(atom, Flag):
        return bool(values[atom.var.name])
    left = values[atom.left.name] if isinstance(atom.left, Var) else atom.left.value
    right = values[atom.right.name] if isinstance(atom.right, Var) else atom.right.value
    if left is ABSENT or right is ABSENT:
        return False
    return _OPS[atom.op](left, right)


# ---------------------------------------------------------------- words

def describe(witness: dict[str, object], units: tuple[tuple[str, str], ...] = ()) -> str:
    """`user.distance = 0.4 m, time_in_state = 16 s` — a witness as a person reads it."""
    unit_of = dict(units)
    if not witness:
        return "always (the conditions hold whatever the percepts are)"
    return ", ".join(_describe_value(name, value, unit_of.get(name))
                     for name, value in witness.items())


def _describe_value(name: str, value: object, unit: str | None) -> str:
    if value is ABSENT:
        return f"{name} absent"
    if isinstance(value, bool):
        return f"{name} = {'true' if value else 'false'}"
    if isinstance(value, str):
        return f'{name} = "{value}"'
    number = f"{value:g}"
    return f"{name} = {number} {unit}" if unit else f"{name} = {number}"
