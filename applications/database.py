"""The application's environment database (SQLite): survey answers, committed one by one.

The schema comes from the application folder (`database.sql`), so an application brings its
own tables. Each answer is committed in its own transaction with synchronous=FULL before the
robot asks the next question: a crash or a power cut loses nothing already answered.
"""
from __future__ import annotations

import sqlite3
import time
import uuid
from pathlib import Path

from applications.exceptions import ApplicationError


class AnswerDatabase:
    def __init__(self, path: str | Path, schema_file: Path | None) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.run_id = uuid.uuid4().hex[:12]
        self._db = sqlite3.connect(self.path, isolation_level=None)
        self._db.execute("PRAGMA synchronous = FULL")
        if schema_file is not None and schema_file.exists():
            try:
                self._db.executescript(schema_file.read_text(encoding="utf-8"))
            except sqlite3.Error as exc:
                raise ApplicationError(f"{schema_file}: the database set-up failed: {exc}") from exc

    def record_answer(self, *, robot: str, session: int, question: str, answer: str,
                      robot_time: float) -> None:
        with self._db:   # one transaction per answer
            self._db.execute(
                "INSERT INTO answers (run_id, robot, session, question, answer, robot_time, wall_time)"
                " VALUES (?, ?, ?, ?, ?, ?, ?)",
                (self.run_id, robot, session, question, answer, robot_time, time.time()))

    def answers(self, run_only: bool = True) -> list[tuple[int, str, str]]:
        """(session, question, answer) rows, oldest first."""
        query = "SELECT session, question, answer FROM answers"
        args: tuple = ()
        if run_only:
            query += " WHERE run_id = ?"
            args = (self.run_id,)
        return list(self._db.execute(query + " ORDER BY id", args))

    def close(self) -> None:
        self._db.close()
