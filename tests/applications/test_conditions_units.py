"""Units are exact: one quantity written in two units compares equal, in the checker and at run
time alike (property tests over every unit pair of a dimension, with decimal literals written
in many ways). The reference arithmetic here uses `decimal`/`fractions`, not the implementation."""
from __future__ import annotations

import math
from decimal import Decimal, localcontext
from fractions import Fraction

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from applications.conditions import compile_condition
from applications.conditions.analysis import EXCLUSIVE, OVERLAP, can_both_be_true
from behaviors.percepts import PerceptSpec as Spec

FACTORS = {"s": Fraction(1), "ms": Fraction(1, 1000), "min": Fraction(60),
           "m": Fraction(1), "cm": Fraction(1, 100)}
DIMENSIONS = {"time": ("s", "ms", "min"), "length": ("m", "cm")}


def declarations(unit: str) -> dict:
    return {"x": Spec("x", "float", unit, (-1e15, 1e15))}


def finite_decimal(value: Fraction) -> bool:
    denominator = value.denominator
    for prime in (2, 5):
        while denominator % prime == 0:
            denominator //= prime
    return denominator == 1


def spellings(value: Fraction, style: int) -> str:
    """A decimal text of `value` (finite decimal), in one of several equivalent spellings."""
    with localcontext() as context:
        context.prec = 60
        exact = Decimal(value.numerator) / Decimal(value.denominator)
    plain = format(exact.normalize(), "f")
    if style == 1 and "." in plain:
        plain += "0"                                   # 0.70
    elif style == 2 and plain.startswith(("0.", "-0.")):
        plain = plain.replace("0.", ".", 1)            # .7
    elif style == 3:
        mantissa = exact.normalize()
        sign, digits, exponent = mantissa.as_tuple()
        text = "".join(map(str, digits)) or "0"
        plain = f"{'-' if sign else ''}{text}e{exponent}"   # 7e-1
    return plain


quantities = st.builds(lambda k, e, negative: Fraction(-k if negative else k) * Fraction(10) ** e,
                       st.integers(0, 10 ** 7), st.integers(-4, 2), st.booleans())
styles = st.integers(0, 3)


@st.composite
def same_quantity_twice(draw):
    """(dimension, percept unit, text A in unit a, text B in unit b) with A == B exactly."""
    dimension = draw(st.sampled_from(sorted(DIMENSIONS)))
    first, second, percept = (draw(st.sampled_from(DIMENSIONS[dimension])) for _ in range(3))
    amount = draw(quantities)                           # in `first`
    other = amount * FACTORS[first] / FACTORS[second]
    assume(finite_decimal(other))
    return (percept, f"{spellings(amount, draw(styles))}{first}",
            f"{spellings(other, draw(styles))}{second}", amount * FACTORS[first])


@settings(max_examples=300, deadline=None)
@given(same_quantity_twice())
def test_one_quantity_in_two_units_is_exclusive_with_its_complement(case) -> None:
    unit, a, b, _ = case
    decl = declarations(unit)
    below, at_least = (compile_condition(f"x < {a}", declarations=decl),
                       compile_condition(f"x >= {b}", declarations=decl))
    above, at_most = (compile_condition(f"x > {a}", declarations=decl),
                      compile_condition(f"x <= {b}", declarations=decl))
    assert can_both_be_true(below, at_least).status == EXCLUSIVE
    assert can_both_be_true(above, at_most).status == EXCLUSIVE


@settings(max_examples=300, deadline=None)
@given(same_quantity_twice())
def test_one_quantity_in_two_units_compares_equal_at_run_time(case) -> None:
    unit, a, b, base = case
    decl = declarations(unit)
    value = float(base / FACTORS[unit])                # the percept reads exactly that quantity
    holds = {text: compile_condition(text, declarations=decl).evaluate({"x": value}, 0)
             for text in (f"x == {a}", f"x == {b}", f"x < {a}", f"x >= {b}", f"x <= {a}",
                          f"x > {b}")}
    assert holds == {f"x == {a}": True, f"x == {b}": True, f"x < {a}": False,
                     f"x >= {b}": True, f"x <= {a}": True, f"x > {b}": False}
    assert compile_condition(f"{a} == {b}").evaluate({}, 0) is True
    assert compile_condition(f"{a} < {b}").evaluate({}, 0) is False


@settings(max_examples=300, deadline=None)
@given(same_quantity_twice())
def test_the_checkers_witness_holds_at_run_time(case) -> None:
    unit, a, b, _ = case
    decl = declarations(unit)
    first = compile_condition(f"x <= {a}", declarations=decl)
    second = compile_condition(f"x >= {b}", declarations=decl)
    verdict = can_both_be_true(first, second)
    assert verdict.status == OVERLAP
    witness = dict(verdict.witness)
    assert first.evaluate(witness, 0) and second.evaluate(witness, 0)
    assert compile_condition(f"x == {a}", declarations=decl).evaluate(witness, 0)
    assert compile_condition(f"x == {b}", declarations=decl).evaluate(witness, 0)


@st.composite
def two_quantities(draw):
    """(percept unit, A, B, exact A, exact B): two quantities of one dimension, often close."""
    dimension = draw(st.sampled_from(sorted(DIMENSIONS)))
    first, second, percept = (draw(st.sampled_from(DIMENSIONS[dimension])) for _ in range(3))
    amount = draw(quantities)
    nudge = draw(st.sampled_from([Fraction(0), Fraction(1, 1000), -Fraction(1, 1000),
                                  Fraction(1, 10), Fraction(-7, 100), Fraction(5)]))
    other = (amount + nudge) * FACTORS[first] / FACTORS[second]
    assume(finite_decimal(other))
    return (percept, f"{spellings(amount, draw(styles))}{first}",
            f"{spellings(other, draw(styles))}{second}",
            amount * FACTORS[first], other * FACTORS[second])


@settings(max_examples=300, deadline=None)
@given(two_quantities())
def test_below_a_and_at_least_b_exclude_each_other_exactly_when_a_is_at_most_b(case) -> None:
    unit, a, b, exact_a, exact_b = case
    decl = declarations(unit)
    first = compile_condition(f"x < {a}", declarations=decl)
    second = compile_condition(f"x >= {b}", declarations=decl)
    verdict = can_both_be_true(first, second)
    assert verdict.status == (EXCLUSIVE if exact_a <= exact_b else OVERLAP)
    if verdict.status == OVERLAP:
        witness = dict(verdict.witness)
        assert first.evaluate(witness, 0) and second.evaluate(witness, 0)


@pytest.mark.parametrize("first, second", [
    ("user.distance < 70cm", "user.distance >= 0.7m"),
    ("user.distance < 0.7m", "user.distance >= 70cm"),
    ("user.distance <= 10cm", "user.distance > 0.1m"),
    ("time_in_state < 100ms", "time_in_state >= 0.1s"),
    ("time_in_state < 0.3min", "time_in_state >= 18s"),
    ("time_in_state < 18000ms", "time_in_state >= 0.3min"),
])
def test_the_issue_examples_are_exclusive_and_agree_at_run_time(first, second) -> None:
    a, b = compile_condition(first), compile_condition(second)
    assert can_both_be_true(a, b).status == EXCLUSIVE
    assert a.tree.right.value == b.tree.right.value          # one float for one quantity
    boundary = b.tree.right.value
    name = "time_in_state" if first.startswith("time") else "user.distance"
    values = {} if name == "time_in_state" else {name: boundary}
    assert a.evaluate(values, boundary) is not b.evaluate(values, boundary)


@settings(max_examples=200, deadline=None)
@given(st.integers(-3600, 3600), st.integers(0, 2), st.integers(0, 2))
def test_equal_angles_in_degrees_compare_equal_against_a_radian_percept(degrees, style_a,
                                                                        style_b) -> None:
    amount = Fraction(degrees, 10)
    decl = {"head.pan": Spec("head.pan", "float", "rad", (-1e3, 1e3))}
    a, b = f"{spellings(amount, style_a)}deg", f"{spellings(amount, style_b)}deg"
    below = compile_condition(f"head.pan < {a}", declarations=decl)
    at_least = compile_condition(f"head.pan >= {b}", declarations=decl)
    assert can_both_be_true(below, at_least).status == EXCLUSIVE
    equal = can_both_be_true(compile_condition(f"head.pan <= {a}", declarations=decl), at_least)
    assert equal.status == OVERLAP
    witness = dict(equal.witness)
    assert not below.evaluate(witness, 0) and at_least.evaluate(witness, 0)
    assert math.isclose(witness["head.pan"], math.radians(degrees / 10), abs_tol=1e-12)


def test_degrees_convert_with_pi_rounded_to_a_float_and_once() -> None:
    decl = {"head.pan": Spec("head.pan", "float", "rad", (-4, 4))}
    condition = compile_condition("head.pan == 90deg", declarations=decl)
    assert condition.tree.right.value == float(90 * Fraction(math.pi) / 180)
    assert condition.evaluate({"head.pan": math.pi / 2}, 0) is True
    assert compile_condition("180deg == 3.141592653589793rad").evaluate({}, 0) is True


@pytest.mark.parametrize("text, fragment", [
    ("time_in_state > 1e301s", "too large"),
    ("time_in_state > 1e-301s", "too small"),
    ("time_in_state > 1e9999999999999", "too large"),
    ("time_in_state > 1" + "0" * 5000, "too large"),
    ("time_in_state > 0." + "0" * 5000 + "1", "too small"),
    ("time_in_state > 1." + "1" * 60, "more than 40 digits"),
])
def test_absurd_numbers_are_errors_not_crashes(text, fragment) -> None:
    from applications.conditions import ConditionError
    with pytest.raises(ConditionError) as caught:
        compile_condition(text)
    assert fragment in caught.value.reason


ANGLE_OPS = ["<", "<=", ">", ">=", "==", "!="]


@settings(max_examples=300, deadline=None)
@given(st.integers(-3600, 3600), st.integers(-6300, 6300), st.sampled_from(ANGLE_OPS),
       st.sampled_from(ANGLE_OPS), st.sampled_from(["deg", "rad"]))
def test_degrees_against_radians_the_checker_and_the_run_time_agree(degrees, centiradians,
                                                                    first_op, second_op,
                                                                    percept_unit) -> None:
    """No exact equality across deg/rad, but whatever the checker says holds at run time, at
    the converted constants and the floats right next to them."""
    decl = {"head.pan": Spec("head.pan", "float", percept_unit, (-1e4, 1e4))}
    first = compile_condition(f"head.pan {first_op} {degrees / 10}deg", declarations=decl)
    second = compile_condition(f"head.pan {second_op} {centiradians / 100}rad",
                               declarations=decl)
    verdict = can_both_be_true(first, second)
    if verdict.status == OVERLAP:
        witness = dict(verdict.witness)
        assert first.evaluate(witness, 0) and second.evaluate(witness, 0)
    else:
        assert verdict.status == EXCLUSIVE
        constants = [first.tree.right.value, second.tree.right.value]
        probes = [f(c) for c in constants for f in (lambda c: c, lambda c: math.nextafter(c, -1e9),
                                                     lambda c: math.nextafter(c, 1e9))]
        for value in probes:
            values = {"head.pan": value}
            assert not (first.evaluate(values, 0) and second.evaluate(values, 0))
