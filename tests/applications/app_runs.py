"""Whole application runs shared by the tests that read them.

A `--fast` run of a bundled application through the real drivers and emulators costs seconds
of CPU; the end-to-end tests of an application, the portability test and the kept-states test
read the very same run (same application, robot, scenario and seed), so each is made once per
test session and its trace and database are read by all. Tests only read what a run left.

Under pytest-xdist the workers share one folder: the first worker that needs a run makes it
while holding a lock on it, and every other worker that needs it waits for the lock and reads
what was left (a `code` file, written last, marks a finished run).
"""
from __future__ import annotations

import fcntl
import sqlite3
from contextlib import contextmanager
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

    def run(self, app: str, robot: str, scenario: str, seed: int = 0,
            wire: bool = False) -> AppRun:
        """`wire`: the whole robot on its wires (`run --wire`): laser, head and tablet too."""
        key = (app, robot, scenario, seed) + (("wire",) if wire else ())
        if key not in self.done:
            where = self.folder / "-".join(map(str, key))
            trace, data, finished = where / "trace.jsonl", where / "data", where / "code"
            with _locked(self.folder / f"{where.name}.lock"):
                if not finished.exists():          # no other worker has made it
                    where.mkdir(parents=True, exist_ok=True)
                    code = main(["run", app, "--robot", robot, "--scenario", scenario,
                                 "--fast", "--seed", str(seed), "--trace", str(trace),
                                 "--data", str(data), "--quiet"] + (["--wire"] if wire else []))
                    finished.write_text(str(code))
            self.done[key] = AppRun(int(finished.read_text()), read_trace(trace), data)
        return self.done[key]


@contextmanager
def _locked(path: Path):
    """An exclusive lock on `path` across processes (held until the block ends)."""
    with open(path, "a") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)
