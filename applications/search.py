"""Finding a row of the application's database by what a person typed: exact, close, or none.

A question in dialog.xml with `search="products"` has its answer looked up in that table: rows
are matched on their `name` (the key), their `label`, their `category` and their `aliases` (a
comma-separated column, optional), case and accents ignored. A typed name that matches none of
them exactly is compared with each by similarity (difflib's ratio, per whole text and per word,
so "expresso" finds "espresso" and "whole milk" finds "milk"): the best row above `CLOSE` is a
*close* match, which the application confirms ("Did you mean …?"); below it the search found
*none* and offers the best few as `suggestions`.

difflib (the standard library) is enough here: a store's catalogue has hundreds of names, each
search compares a few words with each of them once, in milliseconds; rapidfuzz would be faster
on millions of rows but is a compiled dependency this does not need.
"""
from __future__ import annotations

import sqlite3
import unicodedata
from dataclasses import dataclass
from difflib import SequenceMatcher

EXACT, CLOSE_MATCH, NONE = "exact", "close", "none"
OUTCOMES = (EXACT, CLOSE_MATCH, NONE)
CLOSE = 0.75            # similarity from which the best row is offered as "did you mean"
SUGGEST = 0.5           # similarity from which a row is among the suggestions
MAX_SUGGESTIONS = 3

SEARCH_COLUMNS = ("name", "label")                   # a searched table must have these
OPTIONAL_COLUMNS = ("category", "aliases")
SEARCHES_TABLE = "searches"
SEARCH_LOG_COLUMNS = ("run_id", "robot", "session", "question", "query", "outcome", "found",
                      "score", "robot_time", "wall_time")
SEARCHES_TABLE_SQL = """CREATE TABLE IF NOT EXISTS searches (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    run_id      TEXT    NOT NULL,
    robot       TEXT    NOT NULL,
    session     INTEGER NOT NULL,
    question    TEXT    NOT NULL,   -- the question id of dialog.xml
    query       TEXT    NOT NULL,   -- what the person typed or pressed
    outcome     TEXT    NOT NULL,   -- exact, close (did you mean …) or none
    found       TEXT,               -- the row's name (exact or close), else NULL
    score       REAL    NOT NULL,   -- similarity 0..1 of the best row
    robot_time  REAL    NOT NULL,
    wall_time   REAL    NOT NULL
);"""


@dataclass(frozen=True)
class SearchResult:
    query: str
    outcome: str                      # EXACT, CLOSE_MATCH or NONE
    found: str | None                 # the row's name for EXACT and CLOSE_MATCH
    score: float                      # similarity of the best row, 0..1
    suggestions: tuple[str, ...] = ()  # names of the next best rows (NONE: the best ones)


@dataclass(frozen=True)
class Entry:
    name: str
    terms: tuple[str, ...]            # normalized texts the row is known by


def normalize(text: str) -> str:
    """Lower case, accents off, punctuation as spaces, single spaces."""
    decomposed = unicodedata.normalize("NFKD", text)
    plain = "".join(c for c in decomposed if not unicodedata.combining(c)).lower()
    return " ".join("".join(c if c.isalnum() else " " for c in plain).split())


def entries(db: sqlite3.Connection, table: str) -> list[Entry]:
    """The rows of `table` with the texts they are known by."""
    columns = {row[1] for row in db.execute(f"PRAGMA table_info({_quote(table)})")}
    missing = [c for c in SEARCH_COLUMNS if c not in columns]
    if missing:
        raise ValueError(f"table '{table}' cannot be searched: it has no column "
                         f"{', '.join(missing)} (a searched table needs name and label; "
                         f"category and aliases are optional)")
    extra = [c for c in OPTIONAL_COLUMNS if c in columns]
    select = ", ".join(_quote(c) for c in (*SEARCH_COLUMNS, *extra))
    found = []
    for row in db.execute(f"SELECT {select} FROM {_quote(table)}"):
        values = dict(zip((*SEARCH_COLUMNS, *extra), row))
        terms = [values["name"], values["label"], values.get("category") or ""]
        terms += (values.get("aliases") or "").split(",")
        normalized = tuple(dict.fromkeys(t for t in map(normalize, map(str, terms)) if t))
        found.append(Entry(str(values["name"]), normalized))
    return found


def search(rows: list[Entry], query: str) -> SearchResult:
    """The row `query` names: exactly, closely (did you mean), or none (with suggestions)."""
    text = normalize(query)
    if not text:
        return SearchResult(query, NONE, None, 0.0)
    for entry in rows:
        if text in entry.terms:
            return SearchResult(query, EXACT, entry.name, 1.0)
    scored = sorted(((max(similarity(text, term) for term in entry.terms), entry.name)
                     for entry in rows if entry.terms), key=lambda s: -s[0])
    if not scored:
        return SearchResult(query, NONE, None, 0.0)
    best, name = scored[0]
    others = tuple(n for s, n in scored[1:MAX_SUGGESTIONS + 1] if s >= SUGGEST)
    if best >= CLOSE:
        return SearchResult(query, CLOSE_MATCH, name, round(best, 3), others)
    suggestions = tuple(n for s, n in scored[:MAX_SUGGESTIONS] if s >= SUGGEST)
    return SearchResult(query, NONE, None, round(best, 3), suggestions)


def similarity(text: str, term: str) -> float:
    """How alike two normalized texts are, 0..1: as wholes, or the best pair of their words
    (a typo in one word of "whole milk" still finds "milk")."""
    whole = SequenceMatcher(None, text, term).ratio()
    words = [SequenceMatcher(None, a, b).ratio() for a in text.split() for b in term.split()
             if len(a) >= 3 and len(b) >= 3]
    return max([whole, *words])


def _quote(name: str) -> str:
    return '"' + name.replace('"', '""') + '"'
