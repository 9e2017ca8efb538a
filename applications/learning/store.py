"""The learner's statistics in the application's SQLite database: one row per episode (a choice
and its outcome), written and committed as the episode ends, so a restart — or `kill -9` —
loses at most the episode that was still open. The counts a bandit needs are sums over these
rows; nothing else is kept, so the statistics can never disagree with the history.

Per application and robot, per choice point: `frozen` (exploit only), `min_share` (each
alternative gets at least this share of the trials) and `window` (only the newest episodes
count, so the learner follows a world that changes) in `learning_settings`; `reset` deletes a
choice point's episodes (the history that made the old estimate goes with it).
"""
from __future__ import annotations

import sqlite3
import time
from dataclasses import dataclass
from pathlib import Path

SCHEMA = """
CREATE TABLE IF NOT EXISTS learning_episodes (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    app TEXT NOT NULL, robot TEXT NOT NULL, point TEXT NOT NULL, context TEXT NOT NULL,
    alternative TEXT NOT NULL, chosen_by TEXT NOT NULL, success INTEGER NOT NULL,
    after REAL NOT NULL, robot_time REAL NOT NULL, wall_time REAL NOT NULL, run_id TEXT NOT NULL);
CREATE INDEX IF NOT EXISTS learning_episodes_by_point
    ON learning_episodes (app, robot, point, context);
CREATE TABLE IF NOT EXISTS learning_settings (
    app TEXT NOT NULL, robot TEXT NOT NULL, point TEXT NOT NULL,
    frozen INTEGER NOT NULL DEFAULT 0, min_share REAL NOT NULL DEFAULT 0,
    window INTEGER NOT NULL DEFAULT 0,
    PRIMARY KEY (app, robot, point));
"""


@dataclass(frozen=True)
class Settings:
    frozen: bool = False
    min_share: float = 0.0
    window: int = 0           # count only the newest this many episodes per context (0: all)


@dataclass(frozen=True)
class Episode:
    point: str
    context: str
    alternative: str
    chosen_by: str
    success: bool
    after: float              # s from the choice to the outcome
    robot_time: float         # s since the run began, when the outcome was decided
    run_id: str = ""


class LearningStore:
    """Episodes and settings of one application on one robot."""

    def __init__(self, path: str | Path, app: str, robot: str) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.app, self.robot = app, robot
        self.db = sqlite3.connect(self.path, isolation_level=None, timeout=30.0,
                                  check_same_thread=False)
        self.db.execute("PRAGMA synchronous=FULL")       # a commit is on disk before it returns
        self.db.executescript(SCHEMA)
        columns = {row[1] for row in self.db.execute("PRAGMA table_info(learning_settings)")}
        if "window" not in columns:          # a database from before the window setting
            self.db.execute("ALTER TABLE learning_settings ADD COLUMN window INTEGER NOT NULL "
                            "DEFAULT 0")

    def close(self) -> None:
        self.db.close()

    # -- episodes --------------------------------------------------------------------------

    def record(self, episode: Episode) -> None:
        """Write one finished episode (its own transaction: committed when this returns)."""
        self.db.execute(
            "INSERT INTO learning_episodes (app, robot, point, context, alternative, chosen_by, "
            "success, after, robot_time, wall_time, run_id) VALUES (?,?,?,?,?,?,?,?,?,?,?)",
            (self.app, self.robot, episode.point, episode.context, episode.alternative,
             episode.chosen_by, int(episode.success), float(episode.after),
             float(episode.robot_time), time.time(), episode.run_id))

    def counts(self, point: str, context: str | None = None,
               window: int = 0) -> dict[str, tuple[int, int]]:
        """alternative -> (successes, trials), in one context or (None) over all of them; with
        `window`, over the newest `window` episodes only."""
        query = ("SELECT alternative, success FROM learning_episodes "
                 "WHERE app=? AND robot=? AND point=?")
        args: list = [self.app, self.robot, point]
        if context is not None:
            query += " AND context=?"
            args.append(context)
        if window > 0:
            query += " ORDER BY id DESC LIMIT ?"
            args.append(window)
        rows = self.db.execute(f"SELECT alternative, SUM(success), COUNT(*) FROM ({query}) "
                               "GROUP BY alternative", args).fetchall()
        return {alternative: (int(s), int(n)) for alternative, s, n in rows}

    def contexts(self, point: str) -> list[str]:
        rows = self.db.execute("SELECT DISTINCT context FROM learning_episodes WHERE app=? AND "
                               "robot=? AND point=? ORDER BY context",
                               (self.app, self.robot, point)).fetchall()
        return [r[0] for r in rows]

    def history(self, point: str) -> list[tuple[str, str, bool]]:
        """(context, alternative, success) of every episode, oldest first."""
        rows = self.db.execute("SELECT context, alternative, success FROM learning_episodes "
                               "WHERE app=? AND robot=? AND point=? ORDER BY id",
                               (self.app, self.robot, point)).fetchall()
        return [(c, a, bool(s)) for c, a, s in rows]

    def points(self) -> list[str]:
        rows = self.db.execute("SELECT DISTINCT point FROM learning_episodes WHERE app=? AND "
                               "robot=? UNION SELECT point FROM learning_settings WHERE app=? "
                               "AND robot=? ORDER BY 1",
                               (self.app, self.robot, self.app, self.robot)).fetchall()
        return [r[0] for r in rows]

    def reset(self, point: str) -> int:
        """Forget a choice point's episodes; how many there were."""
        cursor = self.db.execute("DELETE FROM learning_episodes WHERE app=? AND robot=? AND "
                                 "point=?", (self.app, self.robot, point))
        return cursor.rowcount

    # -- settings --------------------------------------------------------------------------

    def settings(self, point: str) -> Settings:
        row = self.db.execute("SELECT frozen, min_share, window FROM learning_settings WHERE "
                              "app=? AND robot=? AND point=?",
                              (self.app, self.robot, point)).fetchone()
        return Settings(bool(row[0]), float(row[1]), int(row[2])) if row else Settings()

    def set(self, point: str, frozen: bool | None = None, min_share: float | None = None,
            window: int | None = None) -> None:
        old = self.settings(point)
        new = Settings(old.frozen if frozen is None else frozen,
                       old.min_share if min_share is None else min_share,
                       old.window if window is None else window)
        self.db.execute("INSERT OR REPLACE INTO learning_settings (app, robot, point, frozen, "
                        "min_share, window) VALUES (?,?,?,?,?,?)",
                        (self.app, self.robot, point, int(new.frozen), new.min_share,
                         new.window))


def store_path(data_dir: str | Path, app: str) -> Path:
    """The application's database in the data folder (the answers' file, interbot run)."""
    return Path(data_dir) / f"{app}.sqlite"
