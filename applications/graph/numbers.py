"""Whole numbers in attributes (priority="1"): ASCII digits only, and a fix for everything else.

Python's `int()` and `str.isdigit()` accept digits of every script (١, １) and `isdigit()` even
superscripts that `int()` then refuses; a file is read the same everywhere only when its numbers
are 0-9, so other digits are an error that shows the ASCII spelling.
"""
from __future__ import annotations

import re

from ..conditions.hints import ascii_equivalent

_WHOLE = re.compile(r"[0-9]+")


class NumberSlip(ValueError):
    """Not a whole number; `offset` is the index of the first offending character, `meant` the
    number it clearly stands for (١ is 1, 2.0 is 2), so later checks can go on with it."""

    def __init__(self, message: str, offset: int = 0, meant: int | None = None) -> None:
        super().__init__(message)
        self.offset = offset
        self.meant = meant


def whole_number(value: str, attribute: str, meaning: str = "") -> int:
    """`value` (an attribute's text, surrounding spaces allowed) as an int ≥ 0; NumberSlip with
    the fix otherwise. `meaning` is appended to the generic message (what the number is for)."""
    text = value.strip()
    start = len(value) - len(value.lstrip())
    if _WHOLE.fullmatch(text):
        return int(text)
    wanted = f"{attribute} must be a whole number ≥ 0{meaning}"
    bad = next((i for i, char in enumerate(text) if not "0" <= char <= "9"), 0)
    if not text:
        raise NumberSlip(f"{wanted}, not empty: write e.g. {attribute}=\"1\"", start)
    converted = ascii_equivalent(text)
    if converted and _WHOLE.fullmatch(converted):
        raise NumberSlip(f"{attribute} is written with digits other than 0-9 ({text!r}): "
                         f"write {attribute}=\"{int(converted)}\"", start + bad, int(converted))
    if re.fullmatch(r"-[0-9]+", text):
        raise NumberSlip(f"{wanted}, not {text}: the lowest, 0, is tried first", start)
    if re.fullmatch(r"[0-9]+[.,]0*", text):
        meant = int(re.split("[.,]", text)[0])
        raise NumberSlip(f"{wanted}: write {attribute}=\"{meant}\"", start + bad, meant)
    raise NumberSlip(f"{wanted}, not {value!r}", start + bad)
