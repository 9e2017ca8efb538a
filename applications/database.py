"""The application's environment database (SQLite): its content and what the robot records.

The application folder's `database.sql` sets the database up: the tables the robot writes to
(`answers`, logs) and the content a user edits (rooms, staff, products). It runs on every start,
so it must be safe to run twice (`CREATE TABLE IF NOT EXISTS`, `INSERT OR REPLACE`); the
checker proves that on a copy in memory. Each answer is committed in its own transaction with
synchronous=FULL before the robot asks the next question: a crash loses nothing answered.
"""
from __future__ import annotations

import re
import sqlite3
import time
import uuid
from dataclasses import dataclass
from pathlib import Path

from applications.exceptions import ApplicationError
from applications.graph.diagnostics import Diagnostic, error
from applications.graph.location import Location
from applications.search import SearchResult, entries, search

SCHEMA_FILE = "database.sql"
ANSWER_COLUMNS = ("run_id", "robot", "session", "question", "answer", "robot_time", "wall_time")
# The log of guide runs (GuidePerson) the runtime fills when the application's database.sql
# makes this table: one row per run, with where to, how it ended and why.
GUIDE_RUNS_TABLE = "guide_runs"
GUIDE_RUN_COLUMNS = ("run_id", "robot", "place", "outcome", "reason", "duration", "robot_time",
                     "wall_time")
ANSWERS_TABLE_SQL = """CREATE TABLE IF NOT EXISTS answers (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    run_id      TEXT    NOT NULL,   -- one run of `interbot run`
    robot       TEXT    NOT NULL,
    session     INTEGER NOT NULL,   -- one person's dialog within the run
    question    TEXT    NOT NULL,
    answer      TEXT    NOT NULL,
    robot_time  REAL    NOT NULL,   -- s since the run started
    wall_time   REAL    NOT NULL    -- Unix time
);"""


@dataclass(frozen=True)
class Statement:
    sql: str
    line: int       # where it starts in the file


def statements(text: str) -> list[Statement]:
    """The SQL statements of a script, each with its first line (for file:line messages)."""
    found, pending, start = [], "", 1
    for number, line in enumerate(text.splitlines(keepends=True), 1):
        if not pending.strip():
            start = number
        pending += line
        if sqlite3.complete_statement(pending):
            found.append(Statement(pending.strip(), start))
            pending = ""
    if pending.strip() and not all(l.strip().startswith("--") or not l.strip()
                                   for l in pending.splitlines()):
        found.append(Statement(pending.strip(), start))
    return found


def run_script(db: sqlite3.Connection, path: Path) -> list[Diagnostic]:
    """Run `path` statement by statement; the first failure is returned as a diagnostic."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        return [error(f"cannot read: {exc}", Location(str(path), 1, 1), "database")]
    for statement in statements(text):
        try:
            db.execute(statement.sql)
            _add_new_columns(db, statement)
        except sqlite3.Error as exc:
            line, column = _where_near(statement, str(exc))
            return [error(f"{exc} in: {statement.sql.splitlines()[0][:60]}"
                          + ("" if line == statement.line else
                             f" (the statement starts at line {statement.line})"),
                          Location(str(path), line, column), "database")]
    return []


_CREATE_TABLE = re.compile(r'(?:\s*--[^\n]*\n)*\s*CREATE\s+TABLE\s+IF\s+NOT\s+EXISTS\s+"?(\w+)"?',
                           re.IGNORECASE)          # after the comments that may lead


def _add_new_columns(db: sqlite3.Connection, statement: Statement) -> None:
    """Give a table an older database file already has the columns `database.sql` now
    declares (a new language's texts, say): `CREATE TABLE IF NOT EXISTS` leaves the old table
    as it was, and the rows the script inserts next would fail on it. The rows kept are not
    touched; a column that cannot be added (a key, NOT NULL without a default) is an error
    that says how to add it by hand."""
    match = _CREATE_TABLE.match(statement.sql)
    if not match:
        return
    table = match.group(1)
    have = {row[1] for row in db.execute(f"PRAGMA table_info({_quote(table)})")}
    scratch = sqlite3.connect(":memory:")
    try:
        scratch.execute(statement.sql)
        wanted = list(scratch.execute(f"PRAGMA table_info({_quote(table)})"))
    finally:
        scratch.close()
    for _, name, kind, not_null, default, key in wanted:
        if name in have:
            continue
        if key or (not_null and default is None):
            raise sqlite3.OperationalError(
                f"the database file's table {table} has no column {name}, which this "
                f"statement declares and which cannot be added to kept rows; add it with "
                f"ALTER TABLE {table} ADD COLUMN … (with a default), or move the file away")
        db.execute(f"ALTER TABLE {_quote(table)} ADD COLUMN {_quote(name)} {kind}"
                   + (" NOT NULL" if not_null else "")
                   + (f" DEFAULT {default}" if default is not None else ""))


def _where_near(statement: Statement, message: str) -> tuple[int, int]:
    """Line and column of the text SQLite names in `near "…": syntax error` when it occurs
    once in the statement (so it is surely the place), else the statement's first line."""
    match = re.match(r'near "(.*)": ', message, re.DOTALL)
    at = statement.sql.find(match.group(1)) if match else -1
    if at < 0 or statement.sql.count(match.group(1)) > 1:
        return statement.line, 1
    before = statement.sql[:at]
    return statement.line + before.count("\n"), at - (before.rfind("\n") + 1) + 1


class ApplicationDatabase:
    """The database of one application on disk: set up from `database.sql`, then written to."""

    def __init__(self, path: str | Path, schema_file: Path | None) -> None:
        self.path = Path(path)
        if self.path.parent.exists() and not self.path.parent.is_dir():
            raise ApplicationError(f"{self.path.parent} is a file, not a folder for the database")
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.run_id = uuid.uuid4().hex[:12]
        try:
            self._db = sqlite3.connect(self.path, isolation_level=None, check_same_thread=False)
            self._db.execute("PRAGMA synchronous = FULL")
        except sqlite3.Error as exc:
            raise ApplicationError(f"{self.path}: cannot open the database: {exc}") from None
        if schema_file is not None and schema_file.exists():
            problems = run_script(self._db, schema_file)
            if problems:
                self._db.close()
                raise ApplicationError(f"{problems[0]}", problems)

    def record_answer(self, *, robot: str, session: int, question: str, answer: str,
                      robot_time: float) -> None:
        # A failure here (disk full, file gone) is an output failure the run ends on, with the
        # robot stopped first (applications/shutdown.py), so it is not caught here.
        with self._db:   # one transaction per answer
            self._db.execute(
                "INSERT INTO answers (run_id, robot, session, question, answer, robot_time,"
                " wall_time) VALUES (?, ?, ?, ?, ?, ?, ?)",
                (self.run_id, robot, session, question, answer, robot_time, time.time()))

    def record_guide_run(self, *, robot: str, place: str, outcome: str, reason: str,
                         duration: float, robot_time: float) -> bool:
        """Log one finished guide run in the application's `guide_runs` table, when it has one
        (an application that does not guide has none); True when recorded."""
        if not self._has_table(GUIDE_RUNS_TABLE):
            return False
        with self._db:
            self._db.execute(
                f"INSERT INTO {GUIDE_RUNS_TABLE} (run_id, robot, place, outcome, reason, "
                "duration, robot_time, wall_time) VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (self.run_id, robot, place, outcome, reason, duration, robot_time, time.time()))
        return True

    def _has_table(self, name: str) -> bool:
        return self._db.execute("SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?",
                                (name,)).fetchone() is not None

    def answers(self, run_only: bool = True) -> list[tuple[int, str, str]]:
        """(session, question, answer) rows, oldest first."""
        return self._rows("SELECT session, question, answer FROM answers", run_only)

    def lookup(self, table: str, column: str, key: str) -> str | None:
        return lookup(self._db, table, column, key)

    def columns(self, table: str) -> list[str]:
        return [row[1] for row in self._db.execute(f"PRAGMA table_info({_quote(table)})")]

    def search(self, table: str, query: str, *, robot: str, session: int, question: str,
               robot_time: float, language: str | None = None) -> SearchResult:
        """The row of `table` that `query` names (applications/search.py), logged in the
        searches table with its outcome; labels in `language` where the table has them."""
        result = search(entries(self._db, table), query, language)
        with self._db:
            self._db.execute(
                "INSERT INTO searches (run_id, robot, session, question, query, outcome, found,"
                " score, robot_time, wall_time) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (self.run_id, robot, session, question, query, result.outcome, result.found,
                 result.score, robot_time, time.time()))
        return result

    def searches(self, run_only: bool = True) -> list[tuple[str, str, str, str | None]]:
        """(question, query, outcome, found) rows, oldest first."""
        return self._rows("SELECT question, query, outcome, found FROM searches", run_only)

    def _rows(self, select: str, run_only: bool) -> list[tuple]:
        """The rows of `select`, of this run only or of all, oldest first."""
        if run_only:
            return list(self._db.execute(select + " WHERE run_id = ? ORDER BY id",
                                         (self.run_id,)))
        return list(self._db.execute(select + " ORDER BY id"))

    def close(self) -> None:
        self._db.close()


# The old name, kept for callers that record survey answers only.
AnswerDatabase = ApplicationDatabase


class DatabaseContent:
    """A copy in memory of what `database.sql` sets up: for the checker and for the choices
    and look-ups the dialog and parameters make before the robot runs."""

    def __init__(self, folder: Path) -> None:
        self.path = folder / SCHEMA_FILE
        self.db = sqlite3.connect(":memory:")
        self.problems: list[Diagnostic] = []
        self.exists = self.path.is_file()
        if self.exists:
            self.problems = run_script(self.db, self.path)
            if not self.problems:
                second = run_script(self.db, self.path)
                if second:
                    self.problems = [error(f"{second[0].message} — on the second run: "
                                           f"{SCHEMA_FILE} runs at every start, so write "
                                           "CREATE TABLE IF NOT EXISTS and INSERT OR REPLACE",
                                           second[0].location, "database")]

    @property
    def usable(self) -> bool:
        return self.exists and not self.problems

    def columns(self, table: str) -> list[str]:
        return [row[1] for row in self.db.execute(f"PRAGMA table_info({_quote(table)})")]

    def tables(self) -> list[str]:
        """Tables and views (a view can join tables for a look-up: staff to their room's place)."""
        return [row[0] for row in self.db.execute(
            "SELECT name FROM sqlite_master WHERE type IN ('table', 'view') "
            "AND name NOT LIKE 'sqlite_%'")]

    def key_column(self, table: str) -> str:
        """The table's primary key column, else its first column."""
        rows = list(self.db.execute(f"PRAGMA table_info({_quote(table)})"))
        for row in rows:
            if row[5] == 1:
                return row[1]
        return rows[0][1]

    def keys(self, table: str) -> list[str]:
        key = self.key_column(table)
        return [str(r[0]) for r in _in_file_order(
            self.db, f"SELECT {_quote(key)} FROM {_quote(table)}")]

    def check_column(self, table: str, column: str | None) -> None:
        """ApplicationError naming the tables or columns there are, when one is missing."""
        if not self.exists:
            raise ApplicationError(f"the application has no {SCHEMA_FILE} to read table "
                                   f"'{table}' from")
        if table not in self.tables():
            raise ApplicationError(f"{SCHEMA_FILE} has no table '{table}'; tables: "
                                   f"{', '.join(self.tables()) or 'none'}")
        if column is not None and column not in self.columns(table):
            raise ApplicationError(f"table '{table}' has no column '{column}'; columns: "
                                   f"{', '.join(self.columns(table))}")

    def choices(self, table: str, value: str, label: str | None) -> list[tuple[str, str]]:
        """(value, label) per row of `table`, in file order."""
        self.check_column(table, value)
        if label:
            self.check_column(table, label)
        label = label or value
        return [(str(v), str(l)) for v, l in _in_file_order(
            self.db, f"SELECT {_quote(value)}, {_quote(label)} FROM {_quote(table)}")]

    def missing_answer_columns(self) -> list[str]:
        if "answers" not in self.tables():
            return list(ANSWER_COLUMNS)
        present = set(self.columns("answers"))
        return [c for c in ANSWER_COLUMNS if c not in present]

    def lookup(self, table: str, column: str, key: str) -> str | None:
        return lookup(self.db, table, column, key)


def lookup(db: sqlite3.Connection, table: str, column: str, key: str) -> str | None:
    """`column` of the row of `table` whose key (primary key, else first column) is `key`."""
    rows = list(db.execute(f"PRAGMA table_info({_quote(table)})"))
    if not rows:
        return None
    key_column = next((r[1] for r in rows if r[5] == 1), rows[0][1])
    found = db.execute(f"SELECT {_quote(column)} FROM {_quote(table)} WHERE "
                       f"{_quote(key_column)} = ?", (key,)).fetchone()
    return None if found is None or found[0] is None else str(found[0])


def _in_file_order(db: sqlite3.Connection, select: str) -> list[tuple]:
    """Rows in the order they were inserted (rowid); a view has no rowid and keeps its own."""
    try:
        return list(db.execute(select + " ORDER BY rowid"))
    except sqlite3.OperationalError:
        return list(db.execute(select))


def _quote(name: str) -> str:
    """An identifier quoted for SQL (names come from the application's own files)."""
    return '"' + name.replace('"', '""') + '"'
