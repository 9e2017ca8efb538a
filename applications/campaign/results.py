"""The results of a campaign in one SQLite file: a row per finished run (its settings and what
it gave) and a row per episode of its choice points. Rows are committed as each run finishes,
so an interrupted campaign resumes with the runs it has not finished."""
from __future__ import annotations

import sqlite3
import time
from pathlib import Path
from typing import Any

from applications.campaign.spec import RunSpec

SCHEMA = """
CREATE TABLE IF NOT EXISTS runs (
    key TEXT PRIMARY KEY, grp TEXT NOT NULL, app TEXT NOT NULL, robot TEXT, map TEXT,
    scenario TEXT NOT NULL, seed INTEGER NOT NULL, choose TEXT, learner TEXT NOT NULL,
    freeze INTEGER NOT NULL, exit_code INTEGER NOT NULL, robot_seconds REAL NOT NULL,
    wall_seconds REAL NOT NULL, episodes INTEGER NOT NULL, successes INTEGER NOT NULL,
    surveys INTEGER NOT NULL, answers INTEGER NOT NULL, folder TEXT NOT NULL,
    last_line TEXT NOT NULL, finished REAL NOT NULL);
CREATE TABLE IF NOT EXISTS episodes (
    key TEXT NOT NULL, n INTEGER NOT NULL, point TEXT NOT NULL, context TEXT NOT NULL,
    alternative TEXT NOT NULL, success INTEGER NOT NULL, after REAL NOT NULL, t REAL NOT NULL,
    PRIMARY KEY (key, n));
"""


class Results:
    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.db = sqlite3.connect(self.path)
        self.db.execute("PRAGMA synchronous=FULL")
        self.db.executescript(SCHEMA)

    def close(self) -> None:
        self.db.close()

    def finished(self, failed_too: bool = True) -> set[str]:
        """The keys of the runs that have a result (without `failed_too`: a clean one)."""
        query = "SELECT key FROM runs" + ("" if failed_too else " WHERE exit_code = 0")
        return {row[0] for row in self.db.execute(query)}

    def add(self, run: RunSpec, result: dict[str, Any], folder: Path) -> None:
        episodes = result["episodes"]
        with self.db:
            self.db.execute("DELETE FROM episodes WHERE key=?", (run.key,))
            self.db.execute(
                "INSERT OR REPLACE INTO runs VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)",
                (run.key, run.group, run.app, run.robot, run.map, run.scenario, run.seed,
                 run.choose, run.learner, int(run.freeze), result["exit_code"],
                 result["robot_seconds"], result["wall_seconds"], len(episodes),
                 sum(e["success"] for e in episodes), result["surveys"], result["answers"],
                 str(folder), result["last_line"][0] if result["last_line"] else "",
                 time.time()))
            self.db.executemany(
                "INSERT INTO episodes VALUES (?,?,?,?,?,?,?,?)",
                [(run.key, n, e["point"], e["context"], e["alternative"], int(e["success"]),
                  e["after"], e["t"]) for n, e in enumerate(episodes)])

    def groups(self) -> list[tuple]:
        """Per group (everything but the seed): runs, failed runs, episodes, successes,
        surveys, robot s, wall s."""
        return self.db.execute(
            "SELECT grp, COUNT(*), SUM(exit_code != 0), SUM(episodes), SUM(successes), "
            "SUM(surveys), SUM(robot_seconds), SUM(wall_seconds) FROM runs GROUP BY grp "
            "ORDER BY grp").fetchall()

    def outcomes(self, group: str) -> list[list[bool]]:
        """Each run's episode outcomes in order, for the runs of one group."""
        keys = [r[0] for r in self.db.execute("SELECT key FROM runs WHERE grp=? ORDER BY seed",
                                              (group,))]
        return [[bool(s) for (s,) in self.db.execute(
            "SELECT success FROM episodes WHERE key=? ORDER BY n", (key,))] for key in keys]
