"""Units a condition may write, and how they convert to the unit a percept is declared in."""
from __future__ import annotations

import math

# unit -> (dimension, factor to the dimension's base unit)
UNITS: dict[str, tuple[str, float]] = {
    "s": ("time", 1.0),
    "ms": ("time", 0.001),
    "min": ("time", 60.0),
    "m": ("length", 1.0),
    "cm": ("length", 0.01),
    "deg": ("angle", math.pi / 180.0),
    "rad": ("angle", 1.0),
}

DIMENSION_WORDS = {"time": "a time", "length": "a length", "angle": "an angle"}


def dimension(unit: str) -> str:
    return UNITS[unit][0]


def convert(value: float, from_unit: str, to_unit: str) -> float:
    """`value` written in `from_unit`, expressed in `to_unit` (same dimension)."""
    return value * UNITS[from_unit][1] / UNITS[to_unit][1]


def units_of(dim: str) -> list[str]:
    return [unit for unit, (d, _) in UNITS.items() if d == dim]
