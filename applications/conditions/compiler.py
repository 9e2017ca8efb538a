"""Compile a typed condition into nested closures, once, at load time: per tick a condition
costs a few dictionary look-ups and comparisons — no parsing, no `eval`."""
from __future__ import annotations

import operator
from collections.abc import Callable, Mapping
from typing import Any

from .typed import TIME_IN_STATE, All, Cmp, Const, Flag, Neg, Typed, Value, Var

Evaluator = Callable[[Mapping[str, Any], float], bool]

OPERATORS = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge,
             "==": operator.eq, "!=": operator.ne}


def compile_tree(tree: Typed) -> Evaluator:
    """A function (values, time_in_state) -> bool. Absent (None) values make comparisons false."""
    if isinstance(tree, Const):
        value = tree.value
        return lambda values, t: value
    if isinstance(tree, Flag):
        return _flag(tree.var.name)
    if isinstance(tree, Cmp):
        return _comparison(tree)
    if isinstance(tree, Neg):
        inner = compile_tree(tree.item)
        return lambda values, t: not inner(values, t)
    parts = tuple(compile_tree(item) for item in tree.items)
    if isinstance(tree, All):
        return _all(parts)
    return _any(parts)


def _flag(name: str) -> Evaluator:
    if name == TIME_IN_STATE:
        return lambda values, t: bool(t)
    return lambda values, t: bool(values.get(name))


def _reader(term: Var | Value) -> Evaluator:
    if isinstance(term, Value):
        value = term.value
        return lambda values, t: value
    if term.name == TIME_IN_STATE:
        return lambda values, t: t
    name = term.name
    return lambda values, t: values.get(name)


def _comparison(tree: Cmp) -> Evaluator:
    compare = OPERATORS[tree.op]
    left, right = tree.left, tree.right
    if isinstance(left, Var) and isinstance(right, Value) and left.name != TIME_IN_STATE:
        name, constant = left.name, right.value

        def var_vs_constant(values: Mapping[str, Any], t: float) -> bool:
            value = values.get(name)
            return value is not None and compare(value, constant)
        return var_vs_constant
    read_left, read_right = _reader(left), _reader(right)

    def general(values: Mapping[str, Any], t: float) -> bool:
        a = read_left(values, t)
        if a is None:
            return False
        b = read_right(values, t)
        return b is not None and compare(a, b)
    return general


def _all(parts: tuple[Evaluator, ...]) -> Evaluator:
    if len(parts) == 2:
        first, second = parts
        return lambda values, t: first(values, t) and second(values, t)
    return lambda values, t: all(part(values, t) for part in parts)


def _any(parts: tuple[Evaluator, ...]) -> Evaluator:
    if len(parts) == 2:
        first, second = parts
        return lambda values, t: first(values, t) or second(values, t)
    return lambda values, t: any(part(values, t) for part in parts)
