"""The condition language: grammar, types and units, evaluation with absent values, and the
sandbox — nothing a user writes reaches Python."""
from __future__ import annotations

import pytest

from applications.conditions import CompiledCondition, ConditionError, compile_condition
from applications.graph.location import Location


def holds(text: str, time_in_state: float = 0.0, **values) -> bool:
    values = {name.replace("__", "."): value for name, value in values.items()}
    return compile_condition(text).evaluate(values, time_in_state)


@pytest.mark.parametrize("text, values, t, expected", [
    ("user.distance < 0.75", {"user.distance": 0.5}, 0, True),
    ("user.distance < 0.75m", {"user.distance": 0.8}, 0, False),
    ("user.distance < 75cm", {"user.distance": 0.7}, 0, True),
    ("user.distance < 75cm", {"user.distance": 0.76}, 0, False),
    ("time_in_state > 30s", {}, 31, True),
    ("time_in_state > 30s", {}, 30, False),
    ("time_in_state >= 500ms", {}, 0.5, True),
    ("time_in_state < 1min", {}, 59, True),
    ("time_in_state < 1min", {}, 61, False),
    ("people.count >= 1 and people.new >= 1", {"people.count": 2, "people.new": 1}, 0, True),
    ("not user.present or time_in_state > 15s", {"user.present": True}, 16, True),
    ("not user.present or time_in_state > 15s", {"user.present": True}, 1, False),
    ("not (user.present and survey.done)", {"user.present": True, "survey.done": False}, 0, True),
    ("survey.done == true", {"survey.done": True}, 0, True),
    ("survey.done != false", {"survey.done": False}, 0, False),
    ("true", {}, 0, True),
    ("false or true and false", {}, 0, False),
    ("1m < 2m", {}, 0, True),
    ("100cm == 1m", {}, 0, True),
    ("1min > 61s", {}, 0, False),
])
def test_evaluation(text: str, values: dict, t: float, expected: bool) -> None:
    assert compile_condition(text).evaluate(values, t) is expected


def test_absent_values_make_comparisons_false_and_flags_false() -> None:
    assert holds("user.distance < 1m", user__distance=None) is False
    assert holds("user.distance >= 1m") is False
    assert holds("user.distance != 1m") is False
    assert holds("user.present") is False
    assert holds("not user.present") is True
    assert holds("survey.done == false") is False


def test_angles_in_degrees_compare_with_radian_percepts() -> None:
    from applications.conditions.typed import Value
    declarations = {"head.pan": _spec("head.pan", "float", "rad", (-3.2, 3.2))}
    condition = compile_condition("head.pan > 90deg", declarations=declarations)
    assert condition.evaluate({"head.pan": 1.6}, 0) is True
    assert condition.evaluate({"head.pan": 1.5}, 0) is False
    assert isinstance(condition.tree.right, Value)


def test_strings_compare_with_equality() -> None:
    declarations = {"dialog.answer": _spec("dialog.answer", "str")}
    condition = compile_condition('dialog.answer == "yes" or dialog.answer == \'ja\'',
                                  declarations=declarations)
    assert condition.evaluate({"dialog.answer": "ja"}, 0) is True
    assert condition.evaluate({"dialog.answer": "no"}, 0) is False
    assert condition.evaluate({}, 0) is False
    escaped = compile_condition(r'dialog.answer == "say \"hi\""', declarations=declarations)
    assert escaped.evaluate({"dialog.answer": 'say "hi"'}, 0) is True


def test_names_and_time_use_are_reported() -> None:
    condition = compile_condition("time_in_state > 30s and people.new >= 1 or user.present")
    assert condition.names == frozenset({"people.new", "user.present"})
    assert condition.uses_time is True
    assert isinstance(condition, CompiledCondition)
    assert condition == compile_condition("time_in_state > 30s and people.new >= 1 or user.present")


@pytest.mark.parametrize("text, column, fragment", [
    ("user.distance < 30s", 17, "unit mismatch"),
    ("user.distnce < 1", 1, "did you mean 'user.distance'"),
    ("people.count > 1m", 16, "has no unit"),
    ("survey.done > 1", 15, "true/false"),
    ("survey.done < true", 1, "only == and !="),
    ("user.distance", 1, "not true/false"),
    ("0.5", 1, "is not a condition"),
    ("user.distance < 1 < 2", 19, "cannot be chained"),
    ("user.distance < 1 )", 19, "')' without a matching '('"),
    ("(user.present", 14, "is not closed"),
    ("user.present and", 17, "the condition ends after 'and'"),
    ("user.distance = 1", 15, "write '=='"),
    ("user.present || survey.done", 14, "write 'or'"),
    ("!user.present", 1, "write 'not'"),
    ("time_in_state > 3 h", 19, "write 180min"),
    ("time_in_state > 3h", 18, "unknown unit 'h'"),
    ("time_in_state > 3 s", 19, "right after the number"),
    ('user.present == "yes', 17, "string not closed"),
    ("1 < \"a\"", 1, "cannot compare"),
    ("1s < 1m", 1, "unit mismatch"),
    ("user.distance < people.count", 1, "cannot compare"),
    ("(user.present and survey.done) < 1", 2, "only percepts and values can be compared"),
    ("", 1, "empty condition"),
    ("   ", 1, "empty condition"),
])
def test_errors_point_at_the_column(text: str, column: int, fragment: str) -> None:
    with pytest.raises(ConditionError) as caught:
        compile_condition(text)
    assert caught.value.column == column
    assert fragment in caught.value.reason


@pytest.mark.parametrize("escape", [
    "().__class__",
    "().__class__.__bases__[0].__subclasses__()",
    "lambda: True",
    "(lambda x: x)(1)",
    "user.__class__",
    "user.present.__class__",
    "'{0.__class__}'.format(user)",
    "f'{user}' == 'x'",
    "'%s' % user",
    "__import__('os').system('true')",
    "eval('1')",
    "open('/etc/passwd')",
    "[x for x in ()]",
    "user.present; import os",
    "globals()",
    "user.present if True else False",
    "user['present']",
    "1 + 1 == 2",
    "`id`",
    "\\x41",
])
def test_known_sandbox_escapes_are_rejected_at_load(escape: str) -> None:
    with pytest.raises(ConditionError):
        compile_condition(escape)


def test_error_location_in_file_is_reported() -> None:
    with pytest.raises(ConditionError) as caught:
        compile_condition("user.distance < 30s", Location("graph.xml", 7, 40))
    assert caught.value.column == 56
    assert str(caught.value).startswith("graph.xml:7:56: unit mismatch")


def test_deep_nesting_is_an_error_not_a_crash() -> None:
    with pytest.raises(ConditionError) as caught:
        compile_condition("(" * 500 + "true" + ")" * 500)
    assert "nested" in caught.value.reason
    with pytest.raises(ConditionError):
        compile_condition("not " * 500 + "true")


def _spec(name: str, type_: str, unit: str | None = None, range_=None):
    from behaviors.percepts import PerceptSpec
    return PerceptSpec(name, type_, unit, range_)
