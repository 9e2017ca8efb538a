"""Every slip gets a place and a fix: each way of mistyping an operator, unit, keyword, number or
quote (every entry of the hint tables, and the examples people actually wrote) is an error at
the right column that says what to write instead; and no text whatever ends in anything but a
ConditionError."""
from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from applications.conditions import ConditionError, compile_condition
from applications.conditions.condition import default_declarations
from applications.conditions.hints import (ARITHMETIC, BOOLEAN_WORDS, KEYWORDS, NUMBER_WORDS,
                                           OPERATORS, STRAY, SYMBOLS, TYPOGRAPHIC_QUOTES,
                                           UNIT_ALIASES, WORD_OPERATORS, WORD_PHRASES)
from behaviors.percepts import PerceptSpec as Spec


DECLARATIONS = {**default_declarations(),
                "head.pan": Spec("head.pan", "float", "rad", (-3.2, 3.2)),
                "dialog.answer": Spec("dialog.answer", "str"),
                "answer.office": Spec("answer.office", "str", values=("N1", "N2", "N3"))}
PERCEPT_OF_UNIT = {"s": "time_in_state", "ms": "time_in_state", "min": "time_in_state",
                   "m": "user.distance", "cm": "user.distance", "deg": "head.pan",
                   "rad": "head.pan"}


def error_of(text: str) -> ConditionError:
    with pytest.raises(ConditionError) as caught:
        compile_condition(text, declarations=DECLARATIONS)
    return caught.value


def assert_slip(text: str, column: int, *fragments: str) -> None:
    problem = error_of(text)
    found = (problem.column, *(f in problem.reason for f in fragments))
    assert found == (column, *(True for _ in fragments)), \
        f"{text!r} -> column {problem.column}: {problem.reason}"


# ---------------------------------------------------------------- every table entry

@pytest.mark.parametrize("symbol", sorted(SYMBOLS))
def test_every_symbol_slip_names_what_to_write(symbol: str) -> None:
    meant = SYMBOLS[symbol]
    if meant in OPERATORS:
        assert_slip(f"user.distance {symbol} 1m", 15, f"write '{meant}'")
    elif meant == "not":
        assert_slip(f"{symbol}user.present", 1, "write 'not'")
    else:
        assert_slip(f"user.present {symbol} survey.done", 14, f"write '{meant}'")


@pytest.mark.parametrize("phrase", sorted(WORD_OPERATORS))
@pytest.mark.parametrize("case", [str.lower, str.upper, str.title])
def test_every_word_written_as_an_operator_names_the_operator(phrase, case) -> None:
    written = case(" ".join(phrase))
    if case is not str.lower and written.lower() in KEYWORDS:
        return        # `NOT` is reported as a keyword in the wrong case (tested below)
    assert_slip(f'answer.office {written} "N1"', 15, f"'{WORD_OPERATORS[phrase]}'")


@pytest.mark.parametrize("phrase", sorted(WORD_PHRASES))
def test_every_word_phrase_says_how_to_write_it(phrase) -> None:
    assert_slip(f'answer.office {" ".join(phrase)} "N1"', 15, WORD_PHRASES[phrase])


def _written(amount: Fraction) -> str:
    text = f"{float(amount):.6f}".rstrip("0").rstrip(".")
    assert Fraction(text) == amount
    return text


@pytest.mark.parametrize("alias", sorted(UNIT_ALIASES))
@pytest.mark.parametrize("space", ["", " "])
def test_every_unit_spelling_gets_the_unit_to_write_with_the_converted_number(alias, space):
    unit, factor = UNIT_ALIASES[alias]
    percept = PERCEPT_OF_UNIT[unit]
    column = len(percept) + 5 + len(space)
    assert_slip(f"{percept} < 3{space}{alias}", column, f"unknown unit '{alias}'",
                f"write {_written(3 * factor)}{unit}")


@pytest.mark.parametrize("unit", ["S", "MS", "Min", "M", "CM", "Deg", "RAD"])
def test_units_in_the_wrong_case(unit) -> None:
    meant = unit.lower()
    percept = PERCEPT_OF_UNIT[meant]
    assert_slip(f"{percept} < 3{unit}", len(percept) + 5, f"write 3{meant}")


@pytest.mark.parametrize("keyword", sorted(KEYWORDS))
@pytest.mark.parametrize("case", [str.upper, str.title])
def test_keywords_in_the_wrong_case(keyword, case) -> None:
    written = case(keyword)
    text = {"and": f"user.present {written} survey.done",
            "or": f"user.present {written} survey.done",
            "not": f"{written} user.present", "true": f"user.present == {written}",
            "false": f"user.present == {written}"}[keyword]
    assert_slip(text, text.index(written) + 1, f"write '{keyword}'", "lower case")


@pytest.mark.parametrize("word", sorted(BOOLEAN_WORDS))
def test_yes_no_on_off_for_true_false(word) -> None:
    meant = BOOLEAN_WORDS[word]
    assert_slip(f"user.present == {word}", 17, f"write user.present == {meant}")
    assert_slip(f'user.present != "{word}"', 17, f"write user.present != {meant}", "no quotes")


@pytest.mark.parametrize("quote", list(TYPOGRAPHIC_QUOTES))
def test_typographic_quotes(quote) -> None:
    assert_slip(f"dialog.answer == {quote}yes{quote}", 18, "straight quotes", '"yes"')


@pytest.mark.parametrize("char", sorted(STRAY))
def test_every_stray_character_says_what_was_meant(char) -> None:
    assert_slip(f"user.present {char} survey.done", 14, STRAY[char])


@pytest.mark.parametrize("char", list(ARITHMETIC))
def test_arithmetic_says_to_write_the_result(char) -> None:
    assert_slip(f"people.count > 1 {char} 1", 18, "write the result as one number")


@pytest.mark.parametrize("word", sorted(NUMBER_WORDS))
def test_numbers_written_as_words(word) -> None:
    assert_slip(f"people.count >= {word}", 17, f"write {NUMBER_WORDS[word]}")


def test_a_percept_in_a_unit_the_language_cannot_write_takes_bare_numbers() -> None:
    declarations = {"battery.level": Spec("battery.level", "float", "%", (0, 100))}
    with pytest.raises(ConditionError) as caught:
        compile_condition("battery.level < 20cm", declarations=declarations)
    assert caught.value.column == 17 and "write e.g. battery.level < 20" in caught.value.reason
    assert compile_condition("battery.level < 20", declarations=declarations).evaluate(
        {"battery.level": 10.0}, 0) is True


@pytest.mark.parametrize("digit", ["١", "१", "১", "๑", "１", "𝟏", "¹"])
def test_digits_of_other_scripts_get_the_ascii_digit(digit) -> None:
    assert_slip(f"people.count > {digit}", 16, "write 1")
    assert_slip(f"user.distance < {digit}{digit}cm", 17, "write 11")


# ---------------------------------------------------------------- the slips people made

@pytest.mark.parametrize("text, column, fix", [
    # units
    ("time_in_state > 30 sec", 20, "write 30s"),
    ("time_in_state > 30secs", 19, "write 30s"),
    ("time_in_state > 30 seconds", 20, "write 30s"),
    ("time_in_state > 2mins", 18, "write 2min"),
    ("time_in_state > 2 minutes", 19, "write 2min"),
    ("time_in_state > 1 h", 19, "write 60min"),
    ("time_in_state > 1hour", 18, "write 60min"),
    ("time_in_state > 1.5h", 20, "write 90min"),
    ("time_in_state > 2m", 17, "minutes are written 'min': write 2min"),
    ("time_in_state > 3 s", 19, "write the unit right after the number: 3s"),
    ("user.distance < 70 cms", 20, "write 70cm"),
    ("user.distance < 0.7 meters", 21, "write 0.7m"),
    ("user.distance < 500mm", 20, "write 50cm"),
    ("head.pan < 5 degrees", 14, "write 5deg"),
    ("head.pan < 5°", 13, "write 5deg"),
    ("user.distance<0.75 m", 20, "0.75m"),
    ("user.distance < 30x", 19, "use one of s, ms, min, m, cm, deg, rad"),
    # a unit glued to the wrong thing
    ("user.distance m < 0.75", 15, "user.distance < 0.75m"),
    ("user.distance_cm < 70", 1, "the unit goes on the number"),
    ("user.distance.m < 0.7", 1, "the unit goes on the number"),
    ("user.distance[m] < 0.7", 14, "user.distance < 0.75m"),
    ("time_in_state(s) > 30", 14, "time_in_state < 30s"),
    ("time_in_state > s30", 17, "write 30s"),
    # operators
    ("user.distance ≤ 1m", 15, "write '<='"),
    ("user.distance ≥ 1m", 15, "write '>='"),
    ("user.distance ≠ 1m", 15, "write '!='"),
    ("user.distance =< 1m", 15, "write '<='"),
    ("user.distance => 1m", 15, "write '>='"),
    ("user.distance =! 1m", 15, "write '!='"),
    ("user.distance = 1m", 15, "write '=='"),
    ("user.distance < = 1m", 15, "no space inside an operator: write '<='"),
    ("user.distance ! = 1m", 15, "no space inside an operator: write '!='"),
    ("user.distance <=> 1m", 15, "compare with one of"),
    ("user.distance ＜ 1m", 15, "write <"),
    ("user.present && survey.done", 14, "write 'and'"),
    ("user.present || survey.done", 14, "write 'or'"),
    ("!user.present", 1, "write 'not'"),
    ("user.distance - 1 > 0", 15, "conditions do no arithmetic"),
    # keywords
    ("user.present AND survey.done", 14, "write 'and'"),
    ("user.present Or survey.done", 14, "write 'or'"),
    ("NOT user.present", 1, "write 'not'"),
    ("user.present == True", 17, "write 'true'"),
    ("False", 1, "write 'false'"),
    ("user.present == TRUE", 17, "write 'true'"),
    ("user.present is true", 14, "write '=='"),
    ('answer.office is not "N2"', 15, "write '!='"),
    ('answer.office equals "N2"', 15, "write '=='"),
    ('answer.office in ("N1", "N2")', 15, 'x == "a" or x == "b"'),
    ("user.present not", 14, "'not' goes in front"),
    ("user.present and", 17, "add what must also hold, or delete 'and'"),
    ("user.present or", 16, "delete 'or'"),
    ("user.present and not", 21, "delete 'not'"),
    ("and user.present", 1, "put a condition on each side"),
    ("user.present and or survey.done", 18, "'or' after 'and' has nothing to join"),
    # strings and values
    ("dialog.answer == yes", 18, 'put it in quotes: dialog.answer == "yes"'),
    ("answer.office == N2", 18, 'answer.office == "N2"'),
    ("dialog.answer == “yes”", 18, '"yes"'),
    ("answer.office == 2", 18, 'answer.office == "2"'),
    ('people.count == "3"', 17, "without quotes, e.g. 3"),
    ('user.distance < "0.75m"', 17, "without quotes, e.g. 0.75m"),
    ("user.present == 1", 17, "write user.present == true"),
    ("survey.done > 1", 15, "write survey.done == true"),
    ("user.present ==", 16, "'==' needs a value on its right, e.g. user.present == true"),
    ("user.distance < 1 )", 19, "delete it, or add the '('"),
    ('user.present == "true"', 17, "write user.present == true"),
    # numbers
    ("user.distance < 0,75m", 18, "write 0.75m"),
    ("people.count > 1,5", 17, "write 1.5"),
    ("people.count > 1,000", 17, "write 1000"),
    ("people.count > 1.000,5", 21, "write 1000.5"),
    ("people.count > 1_000", 17, "write 1000"),
    ("people.count > 1'000", 17, "write 1000"),
    ("people.count > 1 000", 18, "e.g. 1000"),
    ("user.distance < 0. 75", 20, "e.g. 0.75"),
    ("user.distance < 1.2.3", 20, "at most one decimal point"),
    ("people.count > ١", 16, "write 1"),
    ("people.count > 1e400", 16, "too large"),
    ("people.count >= one", 17, "write 1"),
    ("time_in_state > 1:30", 18, "write 90s"),
    ("user.distance < 1/2", 18, "conditions do no arithmetic"),
    ("people.count > 1 + 1", 18, "conditions do no arithmetic"),
    ("user.distance < 0.5m; user.present", 21, "join conditions with 'and' or 'or'"),
    ("user.distance < 0.75m and > 0.5m", 27, "repeat the percept, e.g. user.distance >"),
    # names
    ("user. distance < 1", 5, "write user.distance"),
    ("user .distance < 1", 6, "write user.distance"),
    ("user.distance < 0.75m.", 22, "delete it"),
    ("user.distnce < 1", 1, "did you mean 'user.distance'"),
    ("crowd.size > 1", 1, "`interbot percepts` lists the percepts"),
])
def test_common_slips_get_the_column_and_the_fix(text, column, fix) -> None:
    assert_slip(text, column, fix)


def test_a_percept_with_known_values_refuses_another_value_with_a_did_you_mean() -> None:
    problem = error_of('answer.office == "n2"')
    assert problem.column == 18
    assert "did you mean 'N2'" in problem.reason and '"N1", "N2", "N3"' in problem.reason


def test_not_equal_to_an_unknown_value_is_a_warning_that_it_always_holds() -> None:
    condition = compile_condition('answer.office != "N9"', declarations=DECLARATIONS)
    (warning,) = condition.warnings
    assert warning.offset == 17 and "holds whenever it has a value" in warning.reason
    assert compile_condition('answer.office != "N2"', declarations=DECLARATIONS).warnings == ()
    assert compile_condition('dialog.answer == "N9"', declarations=DECLARATIONS).warnings == ()


def test_negative_numbers_are_numbers() -> None:
    condition = compile_condition("head.pan < -30deg", declarations=DECLARATIONS)
    assert condition.evaluate({"head.pan": -0.6}, 0) is True
    assert condition.evaluate({"head.pan": -0.5}, 0) is False


# ---------------------------------------------------------------- nothing else ever escapes

SLIP_PIECES = sorted({*SYMBOLS, *UNIT_ALIASES, *(" ".join(p) for p in WORD_OPERATORS),
                      *(" ".join(p) for p in WORD_PHRASES), *BOOLEAN_WORDS, *KEYWORDS,
                      *(k.upper() for k in KEYWORDS), *TYPOGRAPHIC_QUOTES, *OPERATORS,
                      "user.distance", "time_in_state", "answer.office", "user.present", "(",
                      ")", '"', "'", ",", "_", ".", "-", "0", "0.75", "30", "1e400", "١", "１",
                      "m", "s", "min", "[", "]", "\\", "%", "\u00a0", "é", "½", "²"})


@settings(max_examples=500, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(SLIP_PIECES), st.sampled_from(["", " ", "  "])),
                max_size=10))
@example([("AND", ""), (".", " "), ("é", "")])   # a letter outside A-Z after "NAME. " (crashed)
def test_any_mix_of_slips_compiles_or_raises_condition_error(pieces) -> None:
    text = "".join(piece + space for piece, space in pieces)
    try:
        condition = compile_condition(text, declarations=DECLARATIONS)
    except ConditionError as problem:
        assert 0 <= problem.offset <= len(text) and problem.reason
        return
    assert isinstance(condition.evaluate({}, 0.0), bool)


@settings(max_examples=400, deadline=None)
@given(st.text(max_size=30))
def test_any_unicode_text_compiles_or_raises_condition_error(text) -> None:
    try:
        compile_condition(text, declarations=DECLARATIONS)
    except ConditionError as problem:
        assert 0 <= problem.offset <= len(text) and problem.reason


def _documented_slips() -> list[tuple[str, str]]:
    """The rows of the condition table in docs/graph-language.md ('Common slips')."""
    import re
    from pathlib import Path
    doc = (Path(__file__).parents[2] / "docs" / "graph-language.md").read_text()
    section = doc.split("## Common slips", 1)[1].split("Slips in the XML", 1)[0]
    return re.findall(r"^\| `([^`]+)` \| (.+?) \|$", section, re.MULTILINE)


def test_the_docs_list_the_slips() -> None:
    assert len(_documented_slips()) >= 40


@pytest.mark.parametrize("text, message", _documented_slips())
def test_every_documented_slip_gets_the_documented_message(text, message) -> None:
    assert message.strip() in error_of(text).reason


@settings(max_examples=500, deadline=None)
@given(st.text(alphabet="0123456789.,_'-:eE smhcind°<>=!\"", max_size=14))
def test_any_mangled_number_compiles_or_raises_condition_error(tail) -> None:
    text = f"user.distance < {tail}"
    try:
        compile_condition(text, declarations=DECLARATIONS)
    except ConditionError as problem:
        assert 0 <= problem.offset <= len(text) and problem.reason


@pytest.mark.parametrize("text, reason", [
    ("user. distance > 1 m", "no spaces inside a name: write user.distance"),
    ("user. é", "'.' cannot follow 'user' here"),
])
def test_a_space_after_a_names_dot_says_what_to_write(text, reason) -> None:
    with pytest.raises(ConditionError) as raised:
        compile_condition(text, declarations=DECLARATIONS)
    assert reason in raised.value.reason and raised.value.offset == 4
