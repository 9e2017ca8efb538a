import sqlite3

from applications.database import AnswerDatabase
from applications.graph.loader import find_application


def test_each_answer_is_committed_as_it_is_given(tmp_path):
    db = AnswerDatabase(tmp_path / "survey.sqlite", find_application("survey") / "database.sql")
    db.record_answer(robot="horos", session=1, question="q1", answer="yes", robot_time=12.5)
    # another connection (another process, or the next boot) sees it at once
    with sqlite3.connect(tmp_path / "survey.sqlite") as other:
        rows = list(other.execute("SELECT robot, session, question, answer, robot_time FROM answers"))
    assert rows == [("horos", 1, "q1", "yes", 12.5)]
    db.close()


def test_answers_of_earlier_runs_are_kept(tmp_path):
    schema = find_application("survey") / "database.sql"
    first = AnswerDatabase(tmp_path / "s.sqlite", schema)
    first.record_answer(robot="horos", session=1, question="q1", answer="no", robot_time=1.0)
    first.close()
    second = AnswerDatabase(tmp_path / "s.sqlite", schema)
    second.record_answer(robot="horos", session=1, question="q1", answer="yes", robot_time=2.0)
    assert second.answers() == [(1, "q1", "yes")]
    assert second.answers(run_only=False) == [(1, "q1", "no"), (1, "q1", "yes")]
    second.close()


def test_a_syntax_slip_in_database_sql_points_at_its_line_and_column(tmp_path):
    from applications.database import run_script
    script = tmp_path / "database.sql"
    script.write_text("CREATE TABLE rooms (name TEXT, place TEXT);\n"
                      "INSERT INTO rooms VALUES\n"
                      "  ('N1', 'room_n1'),\n"
                      "  ('N2' 'room_n2');\n")
    (problem,) = run_script(sqlite3.connect(":memory:"), script)
    assert (problem.location.line, problem.location.column) == (4, 9)    # 'room_n2'
    assert problem.message == ('near "\'room_n2\'": syntax error in: INSERT INTO rooms VALUES '
                               '(the statement starts at line 2)')


def test_a_database_file_from_before_a_new_column_gets_it_and_keeps_its_rows(tmp_path):
    """A guide database written before the German texts: its `rooms` table lacks `label_de`,
    which today's database.sql declares and fills; the start adds the column, keeps the
    answers, and the new texts can be read."""
    from applications.database import lookup
    old = tmp_path / "database.sql"
    old.write_text("CREATE TABLE IF NOT EXISTS rooms (name TEXT PRIMARY KEY, label TEXT);\n"
                   "INSERT OR REPLACE INTO rooms VALUES ('N2', 'Room N2');\n"
                   "CREATE TABLE IF NOT EXISTS answers (id INTEGER PRIMARY KEY, answer TEXT);\n"
                   "INSERT INTO answers (answer) VALUES ('kept');\n")
    new = tmp_path / "new.sql"
    new.write_text("-- rooms, now with their German labels\n"
                   "CREATE TABLE IF NOT EXISTS rooms (name TEXT PRIMARY KEY, label TEXT,\n"
                   "    label_de TEXT NOT NULL DEFAULT '');\n"
                   "INSERT OR REPLACE INTO rooms (name, label, label_de) VALUES\n"
                   "    ('N2', 'Room N2', 'Raum N2');\n"
                   "CREATE TABLE IF NOT EXISTS answers (id INTEGER PRIMARY KEY, answer TEXT);\n")
    from applications.database import run_script
    db = sqlite3.connect(tmp_path / "app.sqlite")
    assert run_script(db, old) == []
    assert run_script(db, new) == []
    assert lookup(db, "rooms", "label_de", "N2") == "Raum N2"
    assert list(db.execute("SELECT answer FROM answers")) == [("kept",)]


def test_a_new_column_that_cannot_join_kept_rows_is_refused_with_how_to_add_it(tmp_path):
    from applications.database import run_script
    db = sqlite3.connect(tmp_path / "app.sqlite")
    db.execute("CREATE TABLE rooms (name TEXT)")
    script = tmp_path / "database.sql"
    script.write_text("CREATE TABLE IF NOT EXISTS rooms (name TEXT, floor INTEGER NOT NULL);\n")
    (problem,) = run_script(db, script)
    assert problem.location.line == 1
    assert "has no column floor" in problem.message and "ALTER TABLE rooms" in problem.message
