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
