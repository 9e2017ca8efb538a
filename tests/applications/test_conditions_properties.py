"""Property tests (hypothesis) of the condition parser, evaluator and overlap analysis against a
small reference interpreter written here, independently of the implementation."""
from __future__ import annotations

import operator
from fractions import Fraction

from hypothesis import given, settings
from hypothesis import strategies as st

from applications.conditions import ConditionError, compile_condition
from applications.conditions.analysis import (EXCLUSIVE, OVERLAP, UNDECIDED, can_be_true,
                                              can_both_be_true)
from applications.conditions.nodes import unparse
from applications.conditions.parser import parse

OPS = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge,
       "==": operator.eq, "!=": operator.ne}
NUMERIC = {"user.distance": ("m", {"m": Fraction(1), "cm": Fraction(1, 100)}),
           "people.count": (None, {}),
           "time_in_state": ("s", {"s": Fraction(1), "ms": Fraction(1, 1000),
                                   "min": Fraction(60)})}
FLAGS = ["user.present", "survey.done", "user.left"]

numbers = st.sampled_from([0, 0.5, 0.75, 1, 2, 3, 15, 30, 100])


@st.composite
def comparisons(draw):
    name = draw(st.sampled_from(sorted(NUMERIC)))
    op = draw(st.sampled_from(sorted(OPS)))
    value = draw(numbers)
    _, units = NUMERIC[name]
    unit = draw(st.sampled_from([None, *sorted(units)]))
    return ("cmp", name, op, value, unit)


leaves = st.one_of(comparisons(), st.sampled_from(FLAGS).map(lambda n: ("flag", n)),
                   st.booleans().map(lambda b: ("const", b)))
expressions = st.recursive(
    leaves,
    lambda inner: st.one_of(inner.map(lambda e: ("not", e)),
                            st.tuples(st.sampled_from(["and", "or"]), inner, inner)),
    max_leaves=8)
spaces = st.sampled_from(["", " ", "  ", "\t"])


def render(expr, draw_space=lambda: " ") -> str:
    kind = expr[0]
    if kind == "const":
        return "true" if expr[1] else "false"
    if kind == "flag":
        return expr[1]
    if kind == "cmp":
        _, name, op, value, unit = expr
        return f"{name}{draw_space()}{op}{draw_space()}{value}{unit or ''}"
    if kind == "not":
        return f"not ({render(expr[1], draw_space)})"
    return f"({render(expr[1], draw_space)}){draw_space()} {kind} {draw_space()}({render(expr[2], draw_space)})"


def reference(expr, values: dict, t: float) -> bool:
    kind = expr[0]
    if kind == "const":
        return expr[1]
    if kind == "flag":
        return bool(values.get(expr[1]))
    if kind == "cmp":
        _, name, op, value, unit = expr
        actual = t if name == "time_in_state" else values.get(name)
        if actual is None:
            return False
        factor = NUMERIC[name][1].get(unit, 1) if unit else 1
        return OPS[op](actual, float(Fraction(str(value)) * factor))   # exact, rounded once
    if kind == "not":
        return not reference(expr[1], values, t)
    if kind == "and":
        return reference(expr[1], values, t) and reference(expr[2], values, t)
    return reference(expr[1], values, t) or reference(expr[2], values, t)


percept_values = st.fixed_dictionaries({
    "user.distance": st.one_of(st.none(), st.sampled_from([0.0, 0.5, 0.75, 1.0, 2.0, 30.0]),
                               st.floats(0, 30)),
    "people.count": st.one_of(st.none(), st.integers(0, 200)),
    "user.present": st.one_of(st.none(), st.booleans()),
    "survey.done": st.one_of(st.none(), st.booleans()),
    "user.left": st.one_of(st.none(), st.booleans()),
})
times = st.one_of(st.sampled_from([0.0, 0.5, 1.0, 15.0, 30.0, 60.0]), st.floats(0, 1000))


@settings(max_examples=300, deadline=None)
@given(expressions, percept_values, times)
def test_compiled_conditions_agree_with_the_reference(expr, values, t) -> None:
    condition = compile_condition(render(expr))
    assert condition.evaluate(values, t) is reference(expr, values, t)


@settings(max_examples=200, deadline=None)
@given(expressions, st.data())
def test_whitespace_does_not_change_the_meaning(expr, data) -> None:
    spaced = render(expr, lambda: data.draw(spaces))
    assert compile_condition(spaced).tree == compile_condition(render(expr)).tree


@settings(max_examples=200, deadline=None)
@given(expressions)
def test_unparse_then_parse_is_a_fixed_point(expr) -> None:
    once = unparse(parse(render(expr)))
    assert unparse(parse(once)) == once
    assert compile_condition(once).tree == compile_condition(render(expr)).tree


@settings(max_examples=500, deadline=None)
@given(st.text(alphabet=st.sampled_from(list("abcdeforntu._ ()<>=!'\"0123456789smc&|[]{}:,+-*/\\")),
               max_size=40))
def test_any_text_either_compiles_or_raises_condition_error(text) -> None:
    try:
        condition = compile_condition(text)
    except ConditionError as problem:
        assert 0 <= problem.offset <= len(text)
        return
    assert isinstance(condition.evaluate({}, 0.0), bool)


near_constants = st.sampled_from([0.0, 0.005, 0.0075, 0.01, 0.02, 0.03, 0.15, 0.3, 0.5, 0.75,
                                  1.0, 1.5, 2.0, 2.5, 3.0, 15.0, 29.0, 30.0])
boundary_values = st.fixed_dictionaries({
    "user.distance": st.one_of(st.none(), near_constants,
                               near_constants.map(lambda v: min(30.0, v + 1e-9))),
    "people.count": st.one_of(st.none(), st.sampled_from([0, 1, 2, 3, 4, 15, 16, 30, 99, 100,
                                                          101, 1000])),
    "user.present": st.one_of(st.none(), st.booleans()),
    "survey.done": st.one_of(st.none(), st.booleans()),
    "user.left": st.one_of(st.none(), st.booleans()),
})
boundary_times = st.sampled_from([0.0, 0.001, 0.5, 0.75, 1.0, 2.0, 3.0, 15.0, 15.001, 30.0,
                                  45.0, 60.0, 100.0, 180.0, 1800.0, 6000.0])


@settings(max_examples=300, deadline=None)
@given(expressions, expressions,
       st.lists(st.tuples(st.one_of(percept_values, boundary_values),
                          st.one_of(times, boundary_times)), min_size=30, max_size=30))
def test_overlap_verdicts_are_sound(first, second, samples) -> None:
    a, b = compile_condition(render(first)), compile_condition(render(second))
    verdict = can_both_be_true(a, b)
    assert verdict.status != UNDECIDED     # every percept here has a range: always decidable
    if verdict.status == OVERLAP:
        witness = dict(verdict.witness)
        t = witness.pop("time_in_state", 0.0)
        assert a.evaluate(witness, t) and b.evaluate(witness, t)
    elif verdict.status == EXCLUSIVE:
        for values, t in samples:
            assert not (a.evaluate(values, t) and b.evaluate(values, t))


@settings(max_examples=200, deadline=None)
@given(expressions, percept_values, times)
def test_never_true_verdict_is_sound(expr, values, t) -> None:
    condition = compile_condition(render(expr))
    if condition.evaluate(values, t):
        assert can_be_true(condition).status != EXCLUSIVE


@settings(max_examples=300, deadline=None)
@given(expressions, boundary_values, boundary_times)
def test_compiled_conditions_agree_with_the_reference_at_the_boundaries(expr, values, t) -> None:
    """Percept values exactly at the constants (0.0075 m is 0.75cm): the unit conversion must
    land on the very float the reference computes exactly."""
    condition = compile_condition(render(expr))
    assert condition.evaluate(values, t) is reference(expr, values, t)
