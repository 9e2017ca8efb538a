"""Where something stands in a source file, for messages a person can jump to."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, order=True)
class Location:
    """A 1-based line and column in a file."""

    file: str
    line: int
    column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"

    def shifted(self, columns: int) -> "Location":
        """The same line, `columns` further right (for a spot inside an attribute value)."""
        return Location(self.file, self.line, self.column + columns)
