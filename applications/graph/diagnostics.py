"""Diagnostics: one problem found in an application, printable as `file:line:col: error: msg`
(the format editors and compilers use) and as JSON for tools."""
from __future__ import annotations

import difflib
import json
from collections.abc import Iterable
from dataclasses import dataclass

from .location import Location

ERROR = "error"
WARNING = "warning"


@dataclass(frozen=True)
class Diagnostic:
    severity: str          # ERROR or WARNING
    message: str
    location: Location
    code: str = ""         # a short stable tag, e.g. "unknown-state", for tools and tests

    @property
    def is_error(self) -> bool:
        return self.severity == ERROR

    def __str__(self) -> str:
        return f"{self.location}: {self.severity}: {self.message}"

    def to_dict(self) -> dict:
        return {"file": self.location.file, "line": self.location.line,
                "column": self.location.column, "severity": self.severity,
                "code": self.code, "message": self.message}


def error(message: str, location: Location, code: str = "") -> Diagnostic:
    return Diagnostic(ERROR, message, location, code)


def warning(message: str, location: Location, code: str = "") -> Diagnostic:
    return Diagnostic(WARNING, message, location, code)


def has_errors(diagnostics: Iterable[Diagnostic]) -> bool:
    return any(d.is_error for d in diagnostics)


def sort_diagnostics(diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
    """File order, so the output reads top to bottom like the file."""
    return sorted(diagnostics, key=lambda d: (d.location.file, d.location.line,
                                              d.location.column, d.severity, d.message))


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """` (did you mean 'X'?)` when a known name is close to `name`, else ``."""
    close = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.6)
    if not close:
        lowered = {c.lower(): c for c in candidates}
        if name.lower() in lowered:
            close = [lowered[name.lower()]]
    return f" (did you mean '{close[0]}'?)" if close else ""


def format_text(diagnostics: Iterable[Diagnostic]) -> str:
    return "\n".join(str(d) for d in diagnostics)


def format_json(diagnostics: Iterable[Diagnostic]) -> str:
    items = [d.to_dict() for d in diagnostics]
    summary = {"errors": sum(1 for d in items if d["severity"] == ERROR),
               "warnings": sum(1 for d in items if d["severity"] == WARNING)}
    return json.dumps({"diagnostics": items, **summary}, indent=2)
