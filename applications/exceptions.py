"""Errors of the application layer (L3).

Every error says what failed, where (`file:line:col`) and what would fix it. Errors about a whole
file carry all its problems at once in `.diagnostics`, so one run of the checker shows them all.
"""
from __future__ import annotations

from typing import Any


class ApplicationError(Exception):
    """An application cannot be loaded; `.diagnostics` lists every problem found in one pass."""

    def __init__(self, message: str, diagnostics: list[Any] | None = None) -> None:
        super().__init__(message)
        self.diagnostics: list[Any] = list(diagnostics or [])


class UnknownApplicationError(ApplicationError):
    """No bundled application has this name and no folder with a graph.xml is at this path."""


class UnsafeXmlError(ApplicationError):
    """A document uses a DOCTYPE, entities or another XML feature we refuse for safety."""


class ConditionError(ApplicationError):
    """A condition does not parse or does not type-check.

    `offset` is the 0-based index into the condition text; `column` the 1-based column of the
    problem in the file when the condition's location is known, else in the text.
    """

    def __init__(self, message: str, offset: int, text: str, location: Any | None = None) -> None:
        self.reason = message
        self.offset = offset
        self.text = text
        self.location = location
        where = ""
        if location is not None:
            where = f"{location.file}:{location.line}:{location.column + offset}: "
            self.column = location.column + offset
        else:
            self.column = offset + 1
        super().__init__(f"{where}{message} (at column {offset + 1} of condition {text!r})")


class UnknownScenarioError(UnknownApplicationError):
    """No scenario of that name in the application, and no such file."""


class UnsupportedOnRobotError(UnknownApplicationError):
    """The opened robot lacks a device some behavior of the application needs."""
