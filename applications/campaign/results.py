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
    last_line TEXT NOT NULL, finished REAL NOT NULL, session INTEGER NOT NULL DEFAULT 0,
    cpu_seconds REAL, tick_seconds REAL);
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
        columns = {row[1] for row in self.db.execute("PRAGMA table_info(runs)")}
        if "session" not in columns:            # a results file from before sessions
            self.db.execute("ALTER TABLE runs ADD COLUMN session INTEGER NOT NULL DEFAULT 0")
        for name in ("cpu_seconds", "tick_seconds"):      # ... from before these were kept
            if name not in columns:
                self.db.execute(f"ALTER TABLE runs ADD COLUMN {name} REAL")

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
                "INSERT OR REPLACE INTO runs VALUES "
                "(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)",
                (run.key, run.group, run.app, run.robot, run.map, run.scenario, run.seed,
                 run.choose, run.learner, int(run.freeze), result["exit_code"],
                 result["robot_seconds"], result["wall_seconds"], len(episodes),
                 sum(e["success"] for e in episodes), result["surveys"], result["answers"],
                 str(folder), result["last_line"][0] if result["last_line"] else "",
                 time.time(), run.session, result.get("cpu_seconds"),
                 result.get("tick_seconds")))
            self.db.executemany(
                "INSERT INTO episodes VALUES (?,?,?,?,?,?,?,?)",
                [(run.key, n, e["point"], e["context"], e["alternative"], int(e["success"]),
                  e["after"], e["t"]) for n, e in enumerate(episodes)])

    def groups(self) -> list[tuple]:
        """Per group (everything but the seed): runs, failed runs, episodes, successes,
        surveys, robot s, wall s, CPU s (of the runs whose CPU time is known) and the
        episodes of those runs."""
        return self.db.execute(
            "SELECT grp, COUNT(*), SUM(exit_code != 0), SUM(episodes), SUM(successes), "
            "SUM(surveys), SUM(robot_seconds), SUM(wall_seconds), SUM(cpu_seconds), "
            "SUM(CASE WHEN cpu_seconds IS NULL THEN 0 ELSE episodes END) FROM runs "
            "GROUP BY grp ORDER BY grp").fetchall()

    def outcomes(self, group: str) -> list[list[bool]]:
        """Each seed's episode outcomes in order (the sessions of a chain one after another),
        for the runs of one group."""
        rows = self.db.execute(
            "SELECT runs.seed, episodes.success FROM runs JOIN episodes ON episodes.key = "
            "runs.key WHERE runs.grp=? ORDER BY runs.seed, runs.session, episodes.n", (group,))
        per_seed: dict[int, list[bool]] = {}
        for seed, success in rows:
            per_seed.setdefault(seed, []).append(bool(success))
        return list(per_seed.values())
