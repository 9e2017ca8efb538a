"""Type and unit checking: the second gate. An unknown percept, a number compared with a string,
`user.distance < 30s` — all stop here, at load time, with the column and a way to fix it."""
from __future__ import annotations

import operator
from collections.abc import Mapping
from typing import Any

from ..exceptions import ConditionError
from ..graph.diagnostics import did_you_mean
from .nodes import And, Compare, Literal, Name, Node, Not, Or
from .typed import All, AnyOf, Cmp, Const, Flag, Neg, Typed, Value, Var
from .units import DIMENSION_WORDS, UNITS, convert, dimension

NUMERIC = frozenset({"int", "float"})
_FOLD = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge,
         "==": operator.eq, "!=": operator.ne}


def check(node: Node, text: str, declarations: Mapping[str, Any]) -> Typed:
    """The typed tree of `node`; ConditionError on the first name, type or unit problem."""
    return _Checker(text, declarations).condition(node)


class _Checker:
    def __init__(self, text: str, declarations: Mapping[str, Any]) -> None:
        self.text = text
        self.declarations = declarations

    def fail(self, message: str, node: Node) -> ConditionError:
        return ConditionError(message, node.offset, self.text)

    def condition(self, node: Node) -> Typed:
        if isinstance(node, And):
            return All(tuple(self.condition(item) for item in node.operands))
        if isinstance(node, Or):
            return AnyOf(tuple(self.condition(item) for item in node.operands))
        if isinstance(node, Not):
            return Neg(self.condition(node.operand))
        if isinstance(node, Compare):
            return self.compare(node)
        if isinstance(node, Name):
            return self.flag(node)
        if isinstance(node.value, bool):
            return Const(node.value)
        raise self.fail(f"{_literal_words(node)} is not a condition: compare it with a percept",
                        node)

    def flag(self, node: Name) -> Flag:
        var = self.resolve(node)
        if var.type != "bool":
            raise self.fail(f"'{var.name}' is {_type_words(var)}, not true/false: compare it, "
                            f"e.g. {_example(var)}", node)
        return Flag(var)

    def resolve(self, node: Name) -> Var:
        spec = self.declarations.get(node.name)
        if spec is None:
            hint = did_you_mean(node.name, self.declarations)
            raise self.fail(f"unknown percept '{node.name}'{hint}", node)
        return Var(node.name, spec.type, spec.unit, spec.range)

    def compare(self, node: Compare) -> Typed:
        left, right = node.left, node.right
        if isinstance(left, Literal) and isinstance(right, Literal):
            return self.fold(node)
        if not isinstance(left, (Name, Literal)) or not isinstance(right, (Name, Literal)):
            inner = left if not isinstance(left, (Name, Literal)) else right
            raise self.fail("only percepts and values can be compared; a condition in "
                            "parentheses cannot be an operand of '" + node.op + "'", inner)
        if isinstance(left, Name) and isinstance(right, Name):
            return self.compare_names(node)
        name, literal = (left, right) if isinstance(left, Name) else (right, left)
        var = self.resolve(name)
        value = self.literal_for(var, literal, node)
        pair = (var, value) if name is left else (value, var)
        return Cmp(node.op, *pair)

    def compare_names(self, node: Compare) -> Cmp:
        left, right = self.resolve(node.left), self.resolve(node.right)
        if _kind(left.type) != _kind(right.type):
            raise self.fail(f"cannot compare '{left.name}' ({_type_words(left)}) with "
                            f"'{right.name}' ({_type_words(right)})", node)
        if left.unit != right.unit:
            raise self.fail(f"cannot compare '{left.name}' in {left.unit or 'no unit'} with "
                            f"'{right.name}' in {right.unit or 'no unit'}", node)
        self.check_operator(left, node.op, node)
        return Cmp(node.op, left, right)

    def literal_for(self, var: Var, literal: Literal, node: Compare) -> Value:
        value = literal.value
        if var.type == "bool":
            if not isinstance(value, bool):
                raise self.fail(f"'{var.name}' is true/false; compare it with true or false, "
                                f"or use it alone", literal)
            self.check_operator(var, node.op, node)
            return Value(value)
        if var.type == "str":
            if not isinstance(value, str):
                raise self.fail(f"'{var.name}' is a string; compare it with a quoted string "
                                f"like \"yes\"", literal)
            self.check_operator(var, node.op, node)
            return Value(value)
        if not isinstance(value, float):
            raise self.fail(f"'{var.name}' is {_type_words(var)}; compare it with a number"
                            f"{' in ' + var.unit if var.unit else ''}, not {_literal_words(literal)}",
                            literal)
        return Value(self.number_in_unit(var, literal))

    def number_in_unit(self, var: Var, literal: Literal) -> float:
        if literal.unit is None:
            return literal.value            # a bare number is read in the percept's own unit
        if var.unit is None:
            raise self.fail(f"'{var.name}' has no unit, but {_literal_words(literal)} has one: "
                            f"write the bare number", literal)
        if var.unit not in UNITS or dimension(var.unit) != dimension(literal.unit):
            wanted = dimension(var.unit) if var.unit in UNITS else var.unit
            raise self.fail(f"unit mismatch: '{var.name}' is {DIMENSION_WORDS.get(wanted, wanted)} "
                            f"in {var.unit}, but {_literal_words(literal)} is "
                            f"{DIMENSION_WORDS[dimension(literal.unit)]}: write e.g. "
                            f"{_example(var)}", literal)
        return convert(literal.value, literal.unit, var.unit)

    def check_operator(self, var: Var, op: str, node: Node) -> None:
        if var.type in ("bool", "str") and op not in ("==", "!="):
            raise self.fail(f"'{var.name}' is {_type_words(var)}: only == and != compare it, "
                            f"not {op}", node)

    def fold(self, node: Compare) -> Const:
        left, right = node.left, node.right
        if _literal_kind(left) != _literal_kind(right):
            raise self.fail(f"cannot compare {_literal_words(left)} with "
                            f"{_literal_words(right)}", node)
        a, b = left.value, right.value
        if isinstance(a, float):
            if left.unit and right.unit:
                if dimension(left.unit) != dimension(right.unit):
                    raise self.fail(f"unit mismatch: {_literal_words(left)} vs "
                                    f"{_literal_words(right)}", node)
                a, b = a * UNITS[left.unit][1], b * UNITS[right.unit][1]
        elif node.op not in ("==", "!="):
            raise self.fail(f"only == and != compare {_literal_kind(left)}s", node)
        return Const(bool(_FOLD[node.op](a, b)))


def _kind(type_: str) -> str:
    return "number" if type_ in NUMERIC else type_


def _literal_kind(literal: Literal) -> str:
    if isinstance(literal.value, bool):
        return "bool"
    return "string" if isinstance(literal.value, str) else "number"


def _literal_words(literal: Literal) -> str:
    if isinstance(literal.value, bool):
        return "true" if literal.value else "false"
    if isinstance(literal.value, str):
        return f"the string {literal.value!r}"
    number = f"{literal.value:g}"
    return f"{number}{literal.unit}" if literal.unit else f"the number {number}"


def _type_words(var: Var) -> str:
    if var.type == "bool":
        return "true/false"
    if var.type == "str":
        return "a string"
    noun = "a whole number" if var.type == "int" else "a number"
    return f"{noun} in {var.unit}" if var.unit else noun


def _example(var: Var) -> str:
    if var.type == "bool":
        return var.name
    if var.type == "str":
        return f'{var.name} == "yes"'
    if var.unit in UNITS:
        dim = dimension(var.unit)
        sample = {"time": "30s", "length": "0.75m", "angle": "45deg"}[dim]
        return f"{var.name} < {sample}"
    return f"{var.name} >= 1"
