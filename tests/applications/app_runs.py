"""Whole application runs shared by the tests that read them.

A `--fast` run of a bundled application through the real drivers and emulators costs seconds
of CPU; the end-to-end tests of an application and the portability test read the very same run
(same application, robot, scenario and seed), so each is made once per test session and its
trace and database are read by all. Tests only read what a run left.
"""
from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from pathlib import Path

from applications.cli import main
from applications.trace import read_trace


@dataclass(frozen=True)
class AppRun:
    code: int
    trace: list[dict]
    data: Path           # the --data folder: <app>.sqlite

    def rows(self, app: str, sql: str) -> list[tuple]:
        with sqlite3.connect(self.data / f"{app}.sqlite") as db:
            return [tuple(row) for row in db.execute(sql)]

    @property
    def states(self) -> list[str]:
        return [e["to"] for e in self.trace if e["kind"] == "transition"]


class AppRuns:
    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.done: dict[tuple, AppRun] = {}

    def run(self, app: str, robot: str, scenario: str, seed: int = 0) -> AppRun:
        key = (app, robot, scenario, seed)
        if key not in self.done:
            where = self.folder / "-".join(map(str, key))
            where.mkdir(parents=True)
            trace, data = where / "trace.jsonl", where / "data"
            code = main(["run", app, "--robot", robot, "--scenario", scenario, "--fast",
                         "--seed", str(seed), "--trace", str(trace), "--data", str(data),
                         "--quiet"])
            self.done[key] = AppRun(code, read_trace(trace), data)
        return self.done[key]
