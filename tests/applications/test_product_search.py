"""Finding a product by what a customer typed: exact, close ("did you mean"), none with
suggestions; the shopping database's catalogue; the checker's demands on a searched question."""
from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from applications.appfolder import inspect_folder, load_folder
from applications.database import ApplicationDatabase
from applications.search import (CLOSE_MATCH, EXACT, NONE, entries, normalize, search,
                                 similarity)

SHOPPING = Path(__file__).resolve().parents[2] / "applications" / "bundled" / "shopping"


@pytest.fixture(scope="module")
def catalogue():
    db = sqlite3.connect(":memory:")
    db.executescript((SHOPPING / "database.sql").read_text(encoding="utf-8"))
    return entries(db, "catalogue")


@pytest.mark.parametrize("typed,outcome,found", [
    ("Espresso", EXACT, "espresso"),
    ("  ESPRESSO  ", EXACT, "espresso"),
    ("Joghurt", EXACT, "yoghurt"),                  # its German name
    ("yougurt", CLOSE_MATCH, "yoghurt"),
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


def test_words_match_whole_so_paper_is_not_per(catalogue):
    """"Bananas, per kg": "paper" is two edits from "per", not a word of the label."""
    result = search(catalogue, "toilet paper")
    assert (result.outcome, result.found, result.suggestions) == (NONE, None, ())
    assert similarity("paper", "bananas per kg") == 0.0
    assert similarity("500 g", "spaghetti 500 g") == 0.0       # numbers and units name nothing


def test_a_swap_of_two_letters_is_one_slip_and_the_label_is_offered(catalogue):
    result = search(catalogue, "mlik")
    assert (result.outcome, result.found) == (CLOSE_MATCH, "milk")   # the product, not dairy
    assert result.label == "Fresh milk 1 l"
    assert result.suggestion_labels == ("Dairy",)                   # labels, not names


def test_a_miss_near_some_names_suggests_them_by_label(catalogue):
    result = search(catalogue, "dog food")
    assert (result.outcome, result.found) == (NONE, None)
    assert result.suggestions == ("canned", "cat food")
    assert result.suggestion_labels == ("Canned food", "Cat food, 12 pouches")


def test_glued_and_partly_typed_names(catalogue):
    assert search(catalogue, "mineralwater").found == "mineral water"
    whole_milk = search(catalogue, "whole milk")
    assert (whole_milk.outcome, whole_milk.found) == (CLOSE_MATCH, "milk")


@pytest.mark.parametrize("typed,outcome,found,label", [
    ("Milch", EXACT, "milk", "Frische Milch 1 l"),
    ("Bananen", EXACT, "bananas", "Bananen, pro kg"),
    ("Mlich", CLOSE_MATCH, "milk", "Frische Milch 1 l"),
    ("Süßigkeiten", EXACT, "snacks", "Snacks und Süßigkeiten"),
    ("Suessigkeiten", CLOSE_MATCH, "snacks", "Snacks und Süßigkeiten"),
    ("milk", EXACT, "milk", "Frische Milch 1 l"),      # English names still find the row
])
def test_german_names_find_rows_and_german_labels_are_said(catalogue, typed, outcome, found,
                                                           label):
    result = search(catalogue, typed, "de")
    assert (result.outcome, result.found, result.label) == (outcome, found, label)


def test_without_a_label_in_the_language_the_label_is_used(tmp_path):
    db = sqlite3.connect(":memory:")
    db.executescript("CREATE TABLE t (name TEXT, label TEXT, label_de TEXT);"
                     "INSERT INTO t VALUES ('tea', 'Green tea', 'Grüner Tee'), "
                     "('mate', 'Yerba mate', NULL);")
    rows = entries(db, "t")
    assert search(rows, "Grüner Tee", "de").label == "Grüner Tee"
    assert search(rows, "mate", "de").label == "Yerba mate"
    assert search(rows, "tea", "en").label == "Green tea"


def test_the_shopping_database_runs_twice_and_on_a_file_from_before_german_names(tmp_path):
    db = sqlite3.connect(tmp_path / "shop.sqlite")
    sql = (SHOPPING / "database.sql").read_text(encoding="utf-8")
    before = sql[:sql.index("-- German names")] + sql[sql.index("-- What a customer"):]
    db.executescript(before.replace("LEFT JOIN names_de", "LEFT JOIN (SELECT '' AS name, "
                                    "'' AS label, '' AS aliases)"))
    db.executescript(sql)
    db.executescript(sql)
    assert search(entries(db, "catalogue"), "Katzenfutter", "de").found == "cat food"


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


def searching_run(tmp_path, language):
    from types import SimpleNamespace
    from applications.runtime import Run
    database = ApplicationDatabase(tmp_path / "shop.sqlite", SHOPPING / "database.sql")
    dialog = SimpleNamespace(questions=[{"id": "product", "search": "catalogue"}], language="en")
    lines = []
    run = Run(SimpleNamespace(folder=SHOPPING), SimpleNamespace(name="perses"), dialog=dialog,
              duration=1.0, database=database, echo=lines.append, language=language)
    return run, database, lines


@pytest.mark.parametrize("language,typed,label", [("de", "Milch", "Frische Milch 1 l"),
                                                  ("en", "Milch", "Fresh milk 1 l")])
def test_the_run_says_the_label_in_its_language(tmp_path, language, typed, label):
    from behaviors.percepts import PerceptView
    run, database, lines = searching_run(tmp_path, language)
    try:
        run._search({"t": 1.0, "question": "product", "answer": typed, "session": 1})
        view = run._with_searches(PerceptView({"answer.product": typed}, 1.0,
                                              frozenset({"x.y"})))
    finally:
        database.close()
    assert (view["search.product"], view["found.product"]) == ("exact", "milk")
    assert view["label.product"] == label
    assert view.disabled == {"x.y"}                 # a disabled percept stays disabled
    assert f'-> milk "{label}"' in lines[-1]


def test_the_run_offers_the_suggestions_of_a_miss_by_label(tmp_path):
    from behaviors.percepts import PerceptView
    run, database, lines = searching_run(tmp_path, "en")
    try:
        run._search({"t": 1.0, "question": "product", "answer": "dog food", "session": 1})
        view = run._with_searches(PerceptView({"answer.product": "dog food"}, 1.0))
    finally:
        database.close()
    assert view["search.product"] == "none" and "found.product" not in view
    assert view["suggestions.product"] == "Canned food or Cat food, 12 pouches"
    assert lines[-1].endswith("'dog food': none (did you mean: canned \"Canned food\", "
                              "cat food \"Cat food, 12 pouches\")")
