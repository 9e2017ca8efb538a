"""Units a condition may write, and how they convert to the unit a percept is declared in.

Conversion is exact: a number is read from its decimal text as a fraction, multiplied by exact
unit factors, and rounded to a float once. So the same quantity written in two units gives the
very same float (`70cm` and `0.7m` are both the float nearest to 0.7), in the checker and at run
time alike, since both read the one converted constant.

Angles: π is irrational, so `deg` ↔ `rad` multiplies by π/180 with π the float `math.pi` (taken
exactly as a fraction), then rounds once. Equal angles written in degrees therefore always give
the same float; an angle in degrees equals one in radians when both round to the same float
(`180deg` and `3.141592653589793rad` do). To compare angles exactly, write them in one unit.
"""
from __future__ import annotations

import math
import re
from fractions import Fraction
from functools import lru_cache

# unit -> (dimension, exact factor to the dimension's base unit)
UNITS: dict[str, tuple[str, Fraction]] = {
    "s": ("time", Fraction(1)),
    "ms": ("time", Fraction(1, 1000)),
    "min": ("time", Fraction(60)),
    "m": ("length", Fraction(1)),
    "cm": ("length", Fraction(1, 100)),
    "deg": ("angle", Fraction(math.pi) / 180),
    "rad": ("angle", Fraction(1)),
}

DIMENSION_WORDS = {"time": "a time", "length": "a length", "angle": "an angle"}

MAX_DIGITS = 40          # significant digits a number may have
MAX_EXPONENT = 300       # |e| in 1e300

_DECIMAL = re.compile(r"(-?)([0-9]*)(?:\.([0-9]*))?(?:[eE]([+-]?[0-9]+))?")


class NumberError(ValueError):
    """A number the language cannot represent; the message says why and what to write."""


def dimension(unit: str) -> str:
    return UNITS[unit][0]


@lru_cache(maxsize=4096)       # graphs repeat their numbers; Fractions are immutable
def exact(text: str) -> Fraction:
    """The exact value of a decimal literal (ASCII digits, optional '-', '.', exponent);
    NumberError for text that is no such number or is absurdly long, large or small."""
    match = _DECIMAL.fullmatch(text)
    if match is None or not (match.group(2) or match.group(3)):
        raise NumberError(f"'{text}' is not a number: write e.g. 0.75 or 30")
    sign, whole, fraction, exponent = match.groups()
    fraction = fraction or ""
    whole = whole.lstrip("0")
    significant = (whole + fraction).strip("0")
    if not significant:
        return Fraction(0)
    shown = text if len(text) <= 24 else text[:20] + "…"
    if len(significant) > MAX_DIGITS:
        raise NumberError(f"number {shown} has more than {MAX_DIGITS} digits: round it")
    power = 0
    if exponent:
        magnitude = exponent.lstrip("+-")
        power = int(magnitude) if len(magnitude) <= 6 else 10 ** 6
        power = -power if exponent.startswith("-") else power
    order = len((whole + fraction).lstrip("0")) - len(fraction) + power - 1   # 1e3 -> 3
    if abs(order) > MAX_EXPONENT:
        size = "large" if order > 0 else "small"
        raise NumberError(f"number {shown} is too {size}: the language reads numbers between "
                          f"1e-{MAX_EXPONENT} and 1e{MAX_EXPONENT}")
    fraction = fraction.rstrip("0")                  # keeps every digit string short
    digits = int((whole + fraction).lstrip("0"))
    value = Fraction(digits, 10 ** len(fraction)) * Fraction(10) ** power
    return -value if sign else value


def in_unit(value: Fraction, from_unit: str | None, to_unit: str | None) -> Fraction:
    """`value` written in `from_unit`, expressed exactly in `to_unit` (same dimension; a missing
    unit means the value is already in `to_unit`)."""
    if from_unit is None or from_unit == to_unit or to_unit is None:
        return value
    return value * UNITS[from_unit][1] / UNITS[to_unit][1]


def to_float(value: Fraction) -> float:
    """The one rounding: the float nearest to `value`; NumberError when it does not fit."""
    try:
        result = float(value)
    except OverflowError:
        result = math.inf
    if not math.isfinite(result):
        raise NumberError("number is too large")
    return result


def convert(value: Fraction | float | str, from_unit: str, to_unit: str) -> float:
    """`value` (exact, or a decimal text) written in `from_unit`, as a float in `to_unit`."""
    if isinstance(value, str):
        value = exact(value)
    return to_float(in_unit(Fraction(value), from_unit, to_unit))


def units_of(dim: str) -> list[str]:
    return [unit for unit, (d, _) in UNITS.items() if d == dim]


def decimal_text(value: Fraction, places: int | None = None) -> str:
    """`value` as a decimal without exponent: exact when `places` is None (the value must have
    a finite decimal expansion, as every parsed literal has), else rounded to `places`."""
    if places is None:
        places = 0
        while (value * 10 ** places).denominator != 1:
            places += 1
    rounded = round(value * 10 ** places)
    sign = "-" if rounded < 0 else ""
    whole, part = divmod(abs(rounded), 10 ** places)
    text = f"{whole}.{part:0{places}d}".rstrip("0").rstrip(".") if places else str(whole)
    return sign + text if text != "0" else "0"
