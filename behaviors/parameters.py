"""Parameters a macro-behavior takes from the application: declared with a type, checked early.

A state of the application passes parameters to its behavior (a place, a text, a distance, a
question set); the behavior declares each with a `ParameterSpec`. The application checker
validates every value before the robot moves; at run time the behavior receives the value
already converted (a distance in metres, a duration in seconds).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

# type -> what a person should write, for messages
TYPES = {
    "text": "any text",
    "place": "a place name of the robot's map (e.g. room_n2)",
    "distance": "a distance with its unit (e.g. 1.2m or 120cm)",
    "duration": "a duration with its unit (e.g. 30s, 500ms or 2min)",
    "speed": "a speed with its unit (e.g. 0.4m/s, 40cm/s or 1.5km/h; a bare number is m/s)",
    "number": "a number (e.g. 3 or 0.5)",
    "bool": "true or false",
    "questions": "questions with their answers (given in dialog.xml)",
    "picture": "a picture file in the application folder (PNG, JPEG or SVG)",
}

_UNITS = {"distance": {"m": 1.0, "cm": 0.01, "mm": 0.001},
          "duration": {"s": 1.0, "ms": 0.001, "min": 60.0},
          "speed": {"m/s": 1.0, "cm/s": 0.01, "km/h": 1 / 3.6}}
BASE_UNITS = {"distance": "m", "duration": "s", "speed": "m/s"}   # what the behavior receives
BARE_IN = {"speed": "m/s"}      # a bare number means this unit (pace was a number in m/s)
_QUANTITY = re.compile(r"^\s*([0-9]+(?:\.[0-9]*)?|\.[0-9]+)\s*([a-z/]*)\s*$")


class ParameterError(ValueError):
    """A parameter value that does not fit its declared type (message says what would)."""


@dataclass(frozen=True)
class ParameterSpec:
    type: str                           # one of TYPES
    doc: str = ""
    required: bool = False
    default: Any = None                 # used when the application gives no value

    def __post_init__(self) -> None:
        if self.type not in TYPES:
            raise ValueError(f"unknown parameter type '{self.type}'; types: {', '.join(TYPES)}")

    def describe(self) -> str:
        need = "required" if self.required else (
            f"default {self.default!r}" if self.default is not None else "optional")
        kind = f"{self.type} in {BASE_UNITS[self.type]}" if self.type in BASE_UNITS else self.type
        return f"{kind}, {need}: {self.doc}" if self.doc else f"{kind}, {need}"


def convert(spec: ParameterSpec, text: str) -> Any:
    """The value of `text` written for a parameter of `spec`'s type (ParameterError if wrong)."""
    kind = spec.type
    if kind in ("text", "place", "picture"):
        if not text.strip():
            raise ParameterError(f"is empty; write {TYPES[kind]}")
        return " ".join(text.split()) if kind == "text" else text.strip()
    if kind == "bool":
        word = text.strip().lower()
        if word in ("true", "yes", "1"):
            return True
        if word in ("false", "no", "0"):
            return False
        raise ParameterError(f"{text!r} is not true or false")
    if kind == "number":
        try:
            value = float(text.strip()) if "_" not in text else math.nan + "x"
        except (TypeError, ValueError):
            raise ParameterError(f"{text!r} is not a number; write {TYPES[kind]}") from None
        if not math.isfinite(value):
            raise ParameterError(f"{text!r} is not a finite number")
        return value
    if kind in _UNITS:
        return _quantity(kind, text)
    raise ParameterError(f"a {kind} parameter is given in dialog.xml, not as a value")


def _quantity(kind: str, text: str) -> float:
    units = _UNITS[kind]
    match = _QUANTITY.match(text.replace(",", "."))
    if match is None or "," in text:
        raise ParameterError(f"{text!r} is not {TYPES[kind]}")
    number, unit = match.groups()
    if not unit and kind in BARE_IN:
        unit = BARE_IN[kind]
    if not unit:
        raise ParameterError(f"{text!r} has no unit; write {TYPES[kind]}")
    if unit not in units:
        raise ParameterError(f"unit '{unit}' is not {TYPES[kind].split(' (')[0]}; units: "
                             f"{', '.join(units)}")
    return float(number) * units[unit]
