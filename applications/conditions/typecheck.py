"""Type and unit checking: the second gate. An unknown percept, a number compared with a string,
`user.distance < 30s` — all stop here, at load time, with the column and a way to fix it."""
from __future__ import annotations

import operator
import re
from collections.abc import Mapping
from fractions import Fraction
from typing import Any, NamedTuple

from ..exceptions import ConditionError
from ..graph.diagnostics import did_you_mean
from .constants import PREFIX, unknown_parameter
from .hints import BOOLEAN_WORDS, NUMBER_WORDS, unit_alias
from .nodes import And, Compare, Literal, Name, Node, Not, Or
from .typed import All, AnyOf, Cmp, Const, Flag, Neg, Typed, Value, Var
from .units import (DIMENSION_WORDS, UNITS, NumberError, decimal_text, dimension, in_unit,
                    to_float)

NUMERIC = frozenset({"int", "float"})
_LITERALS_ONLY = "compare a percept with a value, e.g. user.distance < 1m"
_FOLD = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge,
         "==": operator.eq, "!=": operator.ne}


class ConditionWarning(NamedTuple):
    """A condition that compiles but probably does not say what was meant."""
    reason: str
    offset: int            # 0-based index into the condition text


def check(node: Node, text: str, declarations: Mapping[str, Any],
          warnings: list[ConditionWarning] | None = None) -> Typed:
    """The typed tree of `node`; ConditionError on the first name, type or unit problem.
    Warnings (e.g. `!=` with a value the percept never has) are appended to `warnings`."""
    checker = _Checker(text, declarations)
    tree = checker.condition(node)
    if warnings is not None:
        warnings.extend(checker.warnings)
    return tree


class _Checker:
    def __init__(self, text: str, declarations: Mapping[str, Any]) -> None:
        self.text = text
        self.declarations = declarations
        self.warnings: list[ConditionWarning] = []

    def fail(self, message: str, node: Node) -> ConditionError:
        return ConditionError(message, node.offset, self.text)

    def warn(self, message: str, node: Node) -> None:
        self.warnings.append(ConditionWarning(message, node.offset))

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

    def resolve(self, node: Name, other: Var | None = None, op: str | None = None) -> Var:
        """The declaration of `node`; `other` and `op` are the comparison it stands in, which
        tells what an unknown word probably was (an unquoted string, yes for true…)."""
        spec = self.declarations.get(node.name)
        if spec is None:
            raise self.fail(self.unknown_name(node.name, other, op), node)
        values = getattr(spec, "values", None)
        if values is not None and spec.type == "str":
            values = tuple(values)
        else:
            values = None
        return Var(node.name, spec.type, spec.unit, spec.range, values)

    def unknown_name(self, name: str, other: Var | None, op: str | None) -> str:
        if name.startswith(PREFIX):
            return unknown_parameter(name, self.declarations)
        suffix = re.fullmatch(r"(.+?)[._]([^._]+)", name)
        if suffix and suffix.group(1) in self.declarations and (
                suffix.group(2) in UNITS or unit_alias(suffix.group(2))):
            base = suffix.group(1)
            spec = self.declarations[base]
            return (f"unknown percept '{name}': the unit goes on the number, not on the name; "
                    f"write e.g. {_example(Var(base, spec.type, spec.unit, spec.range))}")
        glued = re.fullmatch(r"([A-Za-z]+)([0-9]+)", name)
        if glued and (glued.group(1) in UNITS or unit_alias(glued.group(1))):
            unit = glued.group(1) if glued.group(1) in UNITS else unit_alias(glued.group(1))[0]
            return (f"unknown percept '{name}': the unit goes after the number: write "
                    f"{glued.group(2)}{unit}")
        if name.lower() in NUMBER_WORDS:
            return f"'{name}' is a word, not a number: write {NUMBER_WORDS[name.lower()]}"
        if other is not None and op in ("==", "!=") and "." not in name:
            if other.type == "bool" and name.lower() in BOOLEAN_WORDS:
                return (f"'{other.name}' is true/false: write {other.name} {op} "
                        f"{BOOLEAN_WORDS[name.lower()]}, or use it alone")
            if other.type == "str":
                values = other.values or ()
                close = "" if name in values else did_you_mean(name, values)
                return (f"unknown percept '{name}': to compare with the text {name}, put it in "
                        f'quotes: {other.name} {op} "{name}"{close}')
        close = did_you_mean(name, self.declarations)
        return f"unknown percept '{name}'" + (close or ": `interbot percepts` lists the percepts "
                                                        "a condition can read")

    def compare(self, node: Compare) -> Typed:
        left, right = node.left, node.right
        if isinstance(left, Literal) and isinstance(right, Literal):
            return self.fold(node)
        if not isinstance(left, (Name, Literal)) or not isinstance(right, (Name, Literal)):
            inner = left if not isinstance(left, (Name, Literal)) else right
            raise self.fail("only percepts and values can be compared; a condition in "
                            "parentheses cannot be an operand of '" + node.op + "': put the "
                            "comparison inside the parentheses", inner)
        if isinstance(left, Name) and isinstance(right, Name):
            return self.compare_names(node)
        name, literal = (left, right) if isinstance(left, Name) else (right, left)
        var = self.resolve(name, None, node.op)
        value = self.literal_for(var, literal, node)
        pair = (var, value) if name is left else (value, var)
        return Cmp(node.op, *pair)

    def compare_names(self, node: Compare) -> Cmp:
        if node.left.name not in self.declarations and node.right.name in self.declarations:
            self.resolve(node.left, self.resolve(node.right), node.op)
        left = self.resolve(node.left)
        right = self.resolve(node.right, left, node.op)
        if _kind(left.type) != _kind(right.type):
            raise self.fail(f"cannot compare '{left.name}' ({_type_words(left)}) with "
                            f"'{right.name}' ({_type_words(right)}): compare each with a value "
                            f"of its own kind, e.g. {_example(left)}", node)
        if left.unit != right.unit:
            raise self.fail(f"cannot compare '{left.name}' in {left.unit or 'no unit'} with "
                            f"'{right.name}' in {right.unit or 'no unit'}: percepts compared "
                            "with each other need the same unit; compare each with a value",
                            node)
        self.check_operator(left, node.op, node)
        return Cmp(node.op, left, right)

    def literal_for(self, var: Var, literal: Literal, node: Compare) -> Value:
        value = literal.value
        if var.type == "bool":
            if not isinstance(value, bool):
                raise self.fail(_not_a_boolean(var, literal, node.op), literal)
            self.check_operator(var, node.op, node)
            return Value(value)
        if var.type == "str":
            if not isinstance(value, str):
                shown = value if not isinstance(value, Fraction) else _number_words(literal)
                raise self.fail(f"'{var.name}' is a string; compare it with a quoted string, "
                                f'e.g. {var.name} {node.op} "{shown}"', literal)
            self.check_operator(var, node.op, node)
            self.check_value(var, literal, node.op)
            return Value(value)
        if not isinstance(value, Fraction):
            raise self.fail(_not_a_number(var, literal), literal)
        return Value(self.number_in_unit(var, literal))

    def check_value(self, var: Var, literal: Literal, op: str) -> None:
        """A string percept with known values: == with another value never holds (an error),
        != with another value always holds when present (a warning)."""
        if var.values is None or literal.value in var.values:
            return
        hint = did_you_mean(literal.value, var.values)
        listed = ", ".join(f'"{v}"' for v in var.values) or "none"
        if op == "==":
            raise self.fail(f"'{var.name}' is never {literal.value!r}{hint}; its values: "
                            f"{listed}", literal)
        self.warn(f"'{var.name}' is never {literal.value!r}{hint}, so this '!=' holds whenever "
                  f"it has a value; its values: {listed}", literal)

    def number_in_unit(self, var: Var, literal: Literal) -> float:
        """The literal in the percept's unit, converted exactly and rounded once."""
        if literal.unit is not None and var.unit is None:
            raise self.fail(f"'{var.name}' has no unit, but {_literal_words(literal)} has one: "
                            f"write the bare number", literal)
        if literal.unit is not None and var.unit not in UNITS:
            raise self.fail(f"'{var.name}' is in {var.unit}, which conditions write as a bare "
                            f"number: write e.g. {var.name} < {_number_words(literal)}", literal)
        if literal.unit is not None and dimension(var.unit) != dimension(literal.unit):
            wanted = dimension(var.unit) if var.unit in UNITS else var.unit
            if literal.unit == "m" and wanted == "time":
                raise self.fail(f"'m' is metres; minutes are written 'min': write "
                                f"{_number_words(literal)}min", literal)
            raise self.fail(f"unit mismatch: '{var.name}' is {DIMENSION_WORDS.get(wanted, wanted)} "
                            f"in {var.unit}, but {_literal_words(literal)} is "
                            f"{DIMENSION_WORDS[dimension(literal.unit)]}: write e.g. "
                            f"{_example(var)}", literal)
        try:
            return to_float(in_unit(literal.value, literal.unit, var.unit))
        except NumberError as problem:
            raise self.fail(f"{_literal_words(literal)}: {problem}", literal) from None

    def check_operator(self, var: Var, op: str, node: Node) -> None:
        if var.type in ("bool", "str") and op not in ("==", "!="):
            raise self.fail(f"'{var.name}' is {_type_words(var)}: only == and != compare it, "
                            f"not {op}", node)

    def fold(self, node: Compare) -> Const:
        left, right = node.left, node.right
        if _literal_kind(left) != _literal_kind(right):
            raise self.fail(f"cannot compare {_literal_words(left)} with "
                            f"{_literal_words(right)}: {_LITERALS_ONLY}", node)
        a, b = left.value, right.value
        if isinstance(a, Fraction):
            if left.unit and right.unit:
                if dimension(left.unit) != dimension(right.unit):
                    raise self.fail(f"unit mismatch: {_literal_words(left)} vs "
                                    f"{_literal_words(right)}: {_LITERALS_ONLY}", node)
                # each side as the run time would hold it: in the base unit, rounded once
                a, b = (to_float(a * UNITS[left.unit][1]), to_float(b * UNITS[right.unit][1]))
        elif node.op not in ("==", "!="):
            raise self.fail(f"only == and != compare {_literal_kind(left)}s: "
                            f"{_LITERALS_ONLY}", node)
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
    number = _number_words(literal)
    return f"{number}{literal.unit}" if literal.unit else f"the number {number}"


def _number_words(literal: Literal) -> str:
    value = literal.value
    if value and not Fraction(1, 10 ** 9) <= abs(value) < 10 ** 15:
        return f"{float(value):g}"
    return decimal_text(value)


_QUOTED_NUMBER = re.compile(r"\s*(-?[0-9]*\.?[0-9]+)\s*([a-z]*)\s*")


def _not_a_boolean(var: Var, literal: Literal, op: str) -> str:
    value = literal.value
    op = op if op in ("==", "!=") else "=="
    if isinstance(value, str) and value.strip().lower() in ("true", "false", *BOOLEAN_WORDS):
        word = value.strip().lower()
        meant = BOOLEAN_WORDS.get(word, word)
        return f"'{var.name}' is true/false: write {var.name} {op} {meant} (no quotes)"
    if isinstance(value, Fraction) and value in (0, 1):
        return f"'{var.name}' is true/false: write {var.name} {op} {'true' if value else 'false'}"
    return f"'{var.name}' is true/false; compare it with true or false, or use it alone"


def _not_a_number(var: Var, literal: Literal) -> str:
    unit = f" in {var.unit}" if var.unit else ""
    if isinstance(literal.value, str):
        quoted = _QUOTED_NUMBER.fullmatch(literal.value)
        if quoted and (not quoted.group(2) or quoted.group(2) in UNITS):
            return (f"'{var.name}' is {_type_words(var)}: write the number without quotes, "
                    f"e.g. {quoted.group(1)}{quoted.group(2)}")
    return (f"'{var.name}' is {_type_words(var)}; compare it with a number{unit}, "
            f"not {_literal_words(literal)}")


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
