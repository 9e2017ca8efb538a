"""Finding a product by what a customer typed: exact, close ("did you mean"), none with
suggestions; the shopping database's catalogue; the checker's demands on a searched question."""
from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from applications.appfolder import inspect_folder, load_folder
from applications.database import ApplicationDatabase
from applications.search import CLOSE_MATCH, EXACT, NONE, entries, normalize, search

SHOPPING = Path(__file__).resolve().parents[2] / "applications" / "bundled" / "shopping"


@pytest.fixture(scope="module")
def catalogue():
    db = sqlite3.connect(":memory:")
    db.executescript((SHOPPING / "database.sql").read_text(encoding="utf-8"))
    return entries(db, "catalogue")


@pytest.mark.parametrize("typed,outcome,found", [
    ("Espresso", EXACT, "espresso"),
    ("  ESPRESSO  ", EXACT, "espresso"),
    ("Joghurt", CLOSE_MATCH, "yoghurt"),
    ("yogurt", EXACT, "yoghurt"),                   # an alias
    ("expresso", CLOSE_MATCH, "espresso"),
    ("spagetti", CLOSE_MATCH, "spaghetti"),
    ("bakery", EXACT, "bakery"),                    # a category: its shelf
    ("Crème fraîche", NONE, None),                  # not in the store
    ("", NONE, None),
])
def test_typed_names_are_found_exactly_closely_or_not(catalogue, typed, outcome, found):
    result = search(catalogue, typed)
    assert (result.outcome, result.found) == (outcome, found)


def test_a_miss_offers_the_nearest_names(catalogue):
    result = search(catalogue, "chocolat milk")
    assert result.outcome in (CLOSE_MATCH, NONE)
    names = {result.found, *result.suggestions}
    assert {"chocolate", "milk"} & names


def test_normalize_drops_case_accents_and_punctuation():
    assert normalize("  Crème-Fraîche!! ") == "creme fraiche"


def test_searches_are_logged_with_their_outcome(tmp_path):
    database = ApplicationDatabase(tmp_path / "shop.sqlite", SHOPPING / "database.sql")
    try:
        first = database.search("catalogue", "expresso", robot="perses", session=1,
                                question="product", robot_time=3.0)
        database.search("catalogue", "caviar", robot="perses", session=1, question="product",
                        robot_time=9.0)
        assert first.found == "espresso"
        assert database.searches() == [("product", "expresso", "close", "espresso"),
                                       ("product", "caviar", "none", None)]
        assert database.lookup("catalogue", "place", "espresso") == "shelf_coffee"
    finally:
        database.close()


def test_the_shopping_application_declares_the_search_percepts():
    loaded = load_folder("shopping")
    question = next(q for q in loaded.dialog.questions if q["id"] == "product")
    assert question["search"] == "catalogue"
    assert "espresso" in question["found"] and "bakery" in question["found"]


def _folder(tmp_path, sql: str, search: str = "catalogue") -> Path:
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "graph.xml").write_text(
        '<application name="app" initial="Ask" robot="perses">\n'
        '  <state name="Ask" behavior="Ask">\n'
        '    <transition to="Ask" when="found.product == &quot;tea&quot;"/>\n'
        '  </state>\n</application>\n', encoding="utf-8")
    (folder / "dialog.xml").write_text(
        '<dialog><state name="Ask"><question id="product" text="What?" typed="true" '
        f'search="{search}"/></state></dialog>\n', encoding="utf-8")
    (folder / "database.sql").write_text(sql, encoding="utf-8")
    return folder


ANSWERS = ("CREATE TABLE IF NOT EXISTS answers (id INTEGER PRIMARY KEY, run_id TEXT, robot TEXT,"
           " session INTEGER, question TEXT, answer TEXT, robot_time REAL, wall_time REAL);\n")
CATALOGUE = ("CREATE TABLE IF NOT EXISTS catalogue (name TEXT PRIMARY KEY, label TEXT);\n"
             "INSERT OR REPLACE INTO catalogue VALUES ('tea', 'Tea');\n")


def test_the_checker_wants_the_searches_table(tmp_path):
    _, loaded, found = inspect_folder(_folder(tmp_path, ANSWERS + CATALOGUE))
    assert loaded is None
    assert any("does not create a searches table" in d.message for d in found)


def test_the_checker_names_a_table_that_cannot_be_searched(tmp_path):
    _, loaded, found = inspect_folder(_folder(tmp_path, ANSWERS + CATALOGUE, search="shelves"))
    assert loaded is None
    assert any('search="shelves"' in d.message and "no table 'shelves'" in d.message
               for d in found)


def test_found_values_are_checked_against_the_table(tmp_path):
    sql = ANSWERS + CATALOGUE.replace("'tea', 'Tea'", "'coffee', 'Coffee'")
    from applications.search import SEARCHES_TABLE_SQL
    _, loaded, found = inspect_folder(_folder(tmp_path, sql + SEARCHES_TABLE_SQL))
    assert loaded is None
    assert any('"tea"' in d.message or "tea" in d.message for d in found if d.is_error)
