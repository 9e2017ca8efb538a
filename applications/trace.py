"""The run's trace: one JSON object per event per line, flushed as written.

Every line has `t` (robot time, s) and `kind` (transition, behavior, say, ask, answer, skill,
fault, …) plus the event's fields. Tests and tools read it; a crash loses nothing written.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any


class TraceWriter:
    def __init__(self, path: str | Path | None) -> None:
        self._file = open(path, "w", encoding="utf-8") if path else None

    def write(self, event: dict[str, Any]) -> None:
        if self._file is not None:
            self._file.write(json.dumps(event, default=str) + "\n")
            self._file.flush()

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None


def read_trace(path: str | Path) -> list[dict[str, Any]]:
    with open(path, encoding="utf-8") as f:
        return [json.loads(line) for line in f if line.strip()]
