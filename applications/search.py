"""Finding a row of the application's database by what a person typed: exact, close, or none.

A question in dialog.xml with `search="products"` has its answer looked up in that table: rows
are matched on their `name` (the key), their `label`, their `category` and their `aliases` (a
comma-separated column, optional), and on the names in other languages the table gives
(`label_de`, `aliases_de`: a German customer types "Milch"), case and accents ignored.

A typed name that matches none of them exactly is compared with each, *word by word*: two words
are alike when few letters differ (an edit distance that counts a swap of two neighbours as one
edit: "mlik" is one edit from "milk", "expresso" one from "espresso"), and only words at least
75 % alike count. A row's score is how much of the query its words cover and how much of the
row the query covers ("whole milk" covers all of "milk"), so a short word inside a longer one
counts for nothing ("paper" and the "per" of "Bananas, per kg" are two edits apart) and
numbers and units ("500 g") never match. Glued words are compared with spaces removed
("mineralwater"). The best row from `CLOSE` on is a *close* match, which the application
confirms ("Did you mean …?"); below it the search found *none* and offers the best few rows
from `SUGGEST` on as `suggestions`. Results carry each row's label (in the run's language where
the table has one), which is what the robot says and shows; the name stays the key.

A store's catalogue has hundreds of names and each search compares a few words with each of
them once: plain Python does it in milliseconds.
"""
from __future__ import annotations

import re
import sqlite3
import unicodedata
from dataclasses import dataclass, field

EXACT, CLOSE_MATCH, NONE = "exact", "close", "none"
OUTCOMES = (EXACT, CLOSE_MATCH, NONE)
CLOSE = 0.75            # similarity from which the best row is offered as "did you mean"
SUGGEST = 0.5           # similarity from which a row is among the suggestions
MAX_SUGGESTIONS = 3

SEARCH_COLUMNS = ("name", "label")                   # a searched table must have these
OPTIONAL_COLUMNS = ("category", "aliases")
WORD_ALIKE = 0.75       # two words this alike (1 - edits / longer length) count as the same
LANGUAGE_COLUMN = re.compile(r"(label|aliases)_([a-z]{2})")   # label_de, aliases_de
# Words that name no product: units, counts, little words (English and German).
NOISE = frozenset("""g kg mg l ml cl x per pieces piece bags bag can pack and or of the a an with
for in stk stück stuck pro je und oder mit der die das ein eine fur für""".split())
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
    label: str | None = None          # the found row's label, what the robot says and shows
    suggestion_labels: tuple[str, ...] = ()   # the suggestions' labels, in the same order


@dataclass(frozen=True)
class Entry:
    name: str
    terms: tuple[str, ...]            # normalized texts the row is known by
    labels: dict[str, str] = field(default_factory=dict, compare=False)   # language -> label

    def label(self, language: str | None = None) -> str:
        """The row's label in `language` where the table gives one, else its label."""
        return self.labels.get(language or "") or self.labels.get("") or self.name


def normalize(text: str) -> str:
    """Lower case, accents off, punctuation as spaces, single spaces."""
    decomposed = unicodedata.normalize("NFKD", text.replace("ß", "ss"))
    plain = "".join(c for c in decomposed if not unicodedata.combining(c)).lower()
    return " ".join("".join(c if c.isalnum() else " " for c in plain).split())


def entries(db: sqlite3.Connection, table: str) -> list[Entry]:
    """The rows of `table` with the texts they are known by."""
    columns = [row[1] for row in db.execute(f"PRAGMA table_info({_quote(table)})")]
    missing = [c for c in SEARCH_COLUMNS if c not in columns]
    if missing:
        raise ValueError(f"table '{table}' cannot be searched: it has no column "
                         f"{', '.join(missing)} (a searched table needs name and label; "
                         f"category, aliases and label_<language>/aliases_<language> are "
                         f"optional)")
    extra = [c for c in columns if c in OPTIONAL_COLUMNS or LANGUAGE_COLUMN.fullmatch(c)]
    wanted = (*SEARCH_COLUMNS, *extra)
    select = ", ".join(_quote(c) for c in wanted)
    found = []
    for row in db.execute(f"SELECT {select} FROM {_quote(table)}"):
        values = dict(zip(wanted, row))
        terms = [values["name"], values["label"], values.get("category") or ""]
        labels = {"": str(values["label"])}
        for column in extra:
            text = str(values.get(column) or "")
            if column.startswith("aliases"):
                terms += text.split(",")
            elif column.startswith("label_"):
                terms.append(text)
                if text.strip():
                    labels[column[len("label_"):]] = text.strip()
        normalized = tuple(dict.fromkeys(t for t in map(normalize, map(str, terms)) if t))
        found.append(Entry(str(values["name"]), normalized, labels))
    return found


def search(rows: list[Entry], query: str, language: str | None = None) -> SearchResult:
    """The row `query` names: exactly, closely (did you mean), or none (with suggestions);
    labels in `language` where the table has them."""
    text = normalize(query)
    if not text:
        return SearchResult(query, NONE, None, 0.0)
    for entry in rows:
        if text in entry.terms:
            return SearchResult(query, EXACT, entry.name, 1.0, label=entry.label(language))
    scored = sorted(((max(similarity(text, term) for term in entry.terms), index)
                     for index, entry in enumerate(rows) if entry.terms),
                    key=lambda s: (-s[0], s[1]))
    if not scored:
        return SearchResult(query, NONE, None, 0.0)
    best, first = scored[0]
    if best >= CLOSE:
        others = [rows[i] for s, i in scored[1:MAX_SUGGESTIONS + 1] if s >= SUGGEST]
        return SearchResult(query, CLOSE_MATCH, rows[first].name, round(best, 3),
                            tuple(e.name for e in others), rows[first].label(language),
                            tuple(e.label(language) for e in others))
    offered = [rows[i] for s, i in scored[:MAX_SUGGESTIONS] if s >= SUGGEST]
    return SearchResult(query, NONE, None, round(best, 3), tuple(e.name for e in offered),
                        None, tuple(e.label(language) for e in offered))


def similarity(text: str, term: str) -> float:
    """How alike two normalized texts are, 0..1: word by word (each side's share of words the
    other covers, averaged), or as wholes with spaces removed, whichever is higher."""
    glued = _alike(text.replace(" ", ""), term.replace(" ", ""))
    asked, known = _words(text), _words(term)
    if not asked or not known:
        return glued
    query_covered = sum(max(_alike(a, b) for b in known) for a in asked) / len(asked)
    term_covered = sum(max(_alike(b, a) for a in asked) for b in known) / len(known)
    return max(glued, (query_covered + term_covered) / 2)


def _words(text: str) -> list[str]:
    """The words that can name a product: no numbers, units or little words."""
    return [w for w in text.split() if w not in NOISE and not w.isdigit() and len(w) >= 2]


def _alike(a: str, b: str) -> float:
    """1 - edits / longer length when at least WORD_ALIKE, else 0 (unlike words count nothing)."""
    longer = max(len(a), len(b))
    if not longer:
        return 0.0
    if abs(len(a) - len(b)) > longer * (1 - WORD_ALIKE):
        return 0.0
    score = 1 - _edits(a, b) / longer
    return score if score >= WORD_ALIKE else 0.0


def _edits(a: str, b: str) -> int:
    """Insertions, deletions, substitutions and swaps of two neighbours turning a into b
    (the optimal string alignment distance)."""
    previous2: list[int] = []
    previous = list(range(len(b) + 1))
    for i, x in enumerate(a, 1):
        current = [i] + [0] * len(b)
        for j, y in enumerate(b, 1):
            current[j] = min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + (x != y))
            if i > 1 and j > 1 and x == b[j - 2] and a[i - 2] == y:
                current[j] = min(current[j], previous2[j - 2] + 1)
        previous2, previous = previous, current
    return previous[-1]


def _quote(name: str) -> str:
    return '"' + name.replace('"', '""') + '"'
