"""What people type instead of the condition language, and what to write instead.

Data first: a new slip is one more entry in a table here, and the table-driven tests
(tests/applications/test_conditions_slips.py) try every entry. The lexer, parser and type checker
look these tables up where the slip shows, so each message carries the column and the fix.
"""
from __future__ import annotations

import unicodedata
from fractions import Fraction

from .units import UNITS, decimal_text, exact

KEYWORDS = frozenset({"and", "or", "not", "true", "false"})

# Symbols from programming languages, mathematics and keyboards -> what the language writes.
SYMBOLS: dict[str, str] = {
    "&&": "and", "&": "and", "∧": "and",
    "||": "or", "|": "or", "∨": "or",
    "!": "not", "¬": "not", "~": "not",
    "=": "==", "===": "==", "≡": "==", "<==": "<=", ">==": ">=",
    "!==": "!=", "<>": "!=", "≠": "!=", "=!": "!=", "/=": "!=", "~=": "!=",
    "=<": "<=", "≤": "<=", "≦": "<=", "⩽": "<=",
    "=>": ">=", "≥": ">=", "≧": ">=", "⩾": ">=",
}

# Words written where a comparison operator belongs (lower case; phrases as tuples).
WORD_OPERATORS: dict[tuple[str, ...], str] = {
    ("is", "not"): "!=", ("is",): "==", ("isnt",): "!=",
    ("equals",): "==", ("equal",): "==", ("eq",): "==",
    ("not", "equals"): "!=", ("not", "equal"): "!=", ("ne",): "!=", ("neq",): "!=",
    ("not",): "!=",
    ("lt",): "<", ("le",): "<=", ("lte",): "<=",
    ("gt",): ">", ("ge",): ">=", ("gte",): ">=",
}

# Words written where an operator belongs that have no one-word replacement.
WORD_PHRASES: dict[tuple[str, ...], str] = {
    ("not", "in"): 'compare one value at a time: x != "a" and x != "b"',
    ("in",): 'compare one value at a time: x == "a" or x == "b"',
    ("between",): "write two comparisons: x > 1m and x < 2m",
    ("contains",): 'strings are compared whole: x == "yes"',
    ("xor",): "write (a and not b) or (not a and b)",
    ("then",): "a condition is one test: write the state to go to in the transition's 'to'",
}

# Words written where true/false belong.
BOOLEAN_WORDS: dict[str, str] = {
    "yes": "true", "no": "false", "on": "true", "off": "false", "none": "false",
    "null": "false", "nil": "false",
}

# Numbers written as words.
NUMBER_WORDS: dict[str, int] = {word: number for number, word in enumerate(
    ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
     "eleven", "twelve"))}

# Characters of arithmetic, which conditions do not do.
ARITHMETIC = "+*/^"

# Other stray characters with a likely intent.
STRAY: dict[str, str] = {
    ";": "join conditions with 'and' or 'or', not ';'",
    ",": "join conditions with 'and' or 'or', not ','",
    "#": "a condition has no comments: put notes in an XML comment <!-- … --> next to it",
    "%": "there is no percent unit: write the plain number (e.g. 0.5 for 50%)",
    "{": "conditions have no placeholders or blocks: write a comparison, e.g. user.distance < 1m",
    "}": "conditions have no placeholders or blocks: write a comparison, e.g. user.distance < 1m",
    "$": "percept names are written without '$': e.g. user.distance",
    "@": "percept names are written without '@': e.g. user.distance",
    "?": "conditions have no '?': write the comparison that must hold, e.g. user.present",
    "\\": "'\\' may only escape a quote inside a string: write e.g. \"say \\\"hi\\\"\"",
}

# Unit spellings -> (the unit to write, how many of it one of the spelling is).
UNIT_ALIASES: dict[str, tuple[str, Fraction]] = {
    **dict.fromkeys(("sec", "secs", "second", "seconds", "sek"), ("s", Fraction(1))),
    **dict.fromkeys(("msec", "msecs", "millisecond", "milliseconds"), ("ms", Fraction(1))),
    **dict.fromkeys(("us", "µs", "μs", "microsecond", "microseconds"),
                    ("ms", Fraction(1, 1000))),
    **dict.fromkeys(("mins", "minute", "minutes", "mn"), ("min", Fraction(1))),
    **dict.fromkeys(("h", "hr", "hrs", "hour", "hours"), ("min", Fraction(60))),
    **dict.fromkeys(("cms", "centimeter", "centimeters", "centimetre", "centimetres"),
                    ("cm", Fraction(1))),
    **dict.fromkeys(("mm", "millimeter", "millimeters", "millimetre", "millimetres"),
                    ("cm", Fraction(1, 10))),
    **dict.fromkeys(("meter", "meters", "metre", "metres", "mtr", "mtrs", "mt", "mts"),
                    ("m", Fraction(1))),
    **dict.fromkeys(("km", "kilometer", "kilometers", "kilometre", "kilometres"),
                    ("m", Fraction(1000))),
    **dict.fromkeys(("in", "inch", "inches"), ("cm", Fraction(254, 100))),
    **dict.fromkeys(("ft", "foot", "feet"), ("m", Fraction(3048, 10000))),
    **dict.fromkeys(("°", "degree", "degrees", "degs", "grad"), ("deg", Fraction(1))),
    **dict.fromkeys(("radian", "radians", "rads"), ("rad", Fraction(1))),
}

# Quotes word processors put in for " and '.
TYPOGRAPHIC_QUOTES = "“”„‟‘’‚‛«»‹›「」『』＂＇´`"

OPERATORS = ("<", "<=", ">", ">=", "==", "!=")


def symbol_at(text: str, position: int) -> str | None:
    """The longest known slip symbol starting at `position`, if any."""
    for typed in sorted(SYMBOLS, key=len, reverse=True):
        if text.startswith(typed, position):
            return typed
    return None


def unit_alias(word: str) -> tuple[str, Fraction] | None:
    """(unit, factor) for a spelling of a unit the language writes differently; units in the
    wrong case (`S`, `CM`, `Min`) count too."""
    if word.lower() in UNITS and word not in UNITS:
        return word.lower(), Fraction(1)
    return UNIT_ALIASES.get(word) or UNIT_ALIASES.get(word.lower())


def unit_suggestion(number: str, word: str) -> str | None:
    """What to write for `number` followed by the unit spelling `word` (e.g. 2, hours -> 120min)."""
    alias = unit_alias(word) if word not in UNITS else (word, Fraction(1))
    if alias is None:
        return None
    unit, factor = alias
    try:
        value = exact(number) * factor
    except ValueError:
        return None
    written = number if factor == 1 else decimal_text(value, None if _finite(value) else 4)
    return f"{written}{unit}"


UNIT_SAMPLES = {"s": "30", "ms": "500", "min": "2", "m": "0.75", "cm": "75", "deg": "45",
                "rad": "0.5"}


def unit_on_name(name: str, unit: str) -> str:
    """The message for a unit written on a percept's name (user.distance m, time_in_state(s))."""
    written = unit if unit in UNITS else unit_alias(unit)[0]
    return (f"the unit goes right after the number, not after '{name}': write e.g. "
            f"{name} < {UNIT_SAMPLES.get(written, '1')}{written}")


def _finite(value: Fraction) -> bool:
    denominator = value.denominator
    for prime in (2, 5):
        while denominator % prime == 0:
            denominator //= prime
    return denominator == 1


def ascii_equivalent(text: str) -> str | None:
    """`text` (digits of other scripts, full-width forms, superscripts) as ASCII, or None."""
    out = []
    for char in text:
        digit = unicodedata.decimal(char, None)
        if digit is not None:
            out.append(str(digit))
            continue
        folded = unicodedata.normalize("NFKC", char)
        if not folded.isascii() or folded == char:
            return None
        out.append(folded)
    return "".join(out)


def word_operator(words: list[str]) -> tuple[int, str] | None:
    """For the words at an operator's place: (how many words the slip spans, the message)."""
    lowered = [word.lower() for word in words]
    for table, wrap in ((WORD_PHRASES, None), (WORD_OPERATORS, True)):
        for phrase in sorted(table, key=len, reverse=True):
            if tuple(lowered[:len(phrase)]) == phrase:
                written = " ".join(words[:len(phrase)])
                if phrase == ("not",):
                    return 1, ("'not' goes in front of what it negates (not user.present); to "
                               "compare, write '!='")
                if wrap:
                    return len(phrase), (f"'{written}' is not an operator here: write "
                                         f"'{table[phrase]}'")
                return len(phrase), (f"'{written}' is not part of the condition language: "
                                     f"{table[phrase]}")
    return None


def keyword_case(word: str) -> str | None:
    """The keyword `word` means when written in the wrong case (`AND`, `True`), else None."""
    lowered = word.lower()
    return lowered if lowered in KEYWORDS and word != lowered else None
