"""An application's texts in several languages (issue 25 point 3): dialog.xml's xml:lang texts,
the checker's reports of a missing or an invalid language (file:line:col), the choice of the
run's language, and the bundled applications in English and German."""
import shutil

import pytest

from applications.appfolder import inspect_folder, load_folder
from applications.cli import main
from applications.dialog import check_dialog, load_dialog
from applications.dialog_languages import language_for_run, translated_lookup
from applications.exceptions import ApplicationError
from applications.graph.loader import find_application
from applications.languages import base_language, declared_languages, is_language

BUNDLED = ("survey", "guide", "receptionist", "shopping")


def write(tmp_path, text: str):
    path = tmp_path / "dialog.xml"
    path.write_text(text, encoding="utf-8")
    return path


def messages(path) -> list[str]:
    return [str(d) for d in check_dialog(path)[1]]


def test_language_tags_are_iso_codes_with_an_optional_region():
    assert is_language("en") and is_language("de-AT") and is_language("pt_BR")
    assert not is_language("klingon") and not is_language("english") and not is_language("xx")
    assert base_language("en-us") == "en"
    assert declared_languages("en", "de en") == ("en", "de")
    assert declared_languages(None, "de en") == ("de", "en")


def test_klingon_is_refused_at_its_attribute(tmp_path):
    path = write(tmp_path, '<dialog language="klingon">\n  <behavior name="X"><say>Hi</say>'
                           '</behavior>\n</dialog>\n')
    found = messages(path)
    assert found == [f"{path}:1:19: error: 'klingon' is not a language: write an ISO 639-1 "
                     "code, optionally with a region (en, de, fr, en-us, de-at)"]


def test_a_text_missing_in_a_declared_language_is_reported_where_the_text_is(tmp_path):
    path = write(tmp_path, '<dialog language="en" languages="en de">\n'
                           '  <state name="A">\n'
                           '    <say>Hello</say>\n'
                           '    <say xml:lang="de">Hallo</say>\n'
                           '    <closing>Bye</closing>\n'
                           '  </state>\n</dialog>\n')
    found = messages(path)
    assert len(found) == 1
    assert found[0].startswith(f"{path}:5:5: error: <closing> has no German (de) text: add "
                               '<closing xml:lang="de">')


def test_a_question_needs_its_text_and_every_answer_in_each_language(tmp_path):
    path = write(tmp_path, '<dialog languages="en de">\n'
                           '  <state name="A">\n'
                           '    <question id="q" text="Yes or no?">\n'
                           '      <answer>yes</answer><answer>no</answer>\n'
                           '      <answer value="yes" xml:lang="de">ja</answer>\n'
                           '      <answer value="maybe" xml:lang="de">vielleicht</answer>\n'
                           '    </question>\n  </state>\n</dialog>\n')
    found = "\n".join(messages(path))
    assert f"{path}:3:28: error: question 'q' has no German (de) text" in found
    assert f"{path}:3:5: error: answer 'no' of question 'q' has no German (de) label" in found
    assert "translates no answer of question 'q' (values: yes, no)" in found


def test_an_undeclared_language_and_a_translation_without_value_are_reported(tmp_path):
    path = write(tmp_path, '<dialog language="en">\n'
                           '  <state name="A">\n'
                           '    <say>Hello</say>\n'
                           '    <say xml:lang="fr">Bonjour</say>\n'
                           '    <question id="q" text="Yes?"><answer>yes</answer>'
                           '<answer xml:lang="en">no</answer></question>\n'
                           '  </state>\n</dialog>\n')
    found = "\n".join(messages(path))
    assert (f"{path}:4:10: error: xml:lang=\"fr\": French (fr) is not one of the application's "
            "languages (en)") in found
    # xml:lang of the default language is the default text: no error for it
    assert found.count("error") == 1


def test_the_dialog_in_german_keeps_the_values_and_accepts_the_english_labels(tmp_path):
    dialog = load_dialog(find_application("survey") / "dialog.xml")
    assert dialog.languages == ("en", "de")
    german = dialog.in_language("de")
    q1 = german.params_for("Interaction", "Survey")["questions"][0]
    assert q1["text"] == "Arbeiten Sie gern auf diesem Flur?"
    assert q1["buttons"] == ["ja", "nein"] and q1["values"] == ["yes", "no"]
    assert q1["aliases"] == {"yes": "yes", "no": "no"}
    assert german.params_for("Wait", "FaceUser")["say"].startswith("Hallo! Ich bin HOROS.")
    english = dialog.in_language("en")
    assert english.params_for("Wait", "FaceUser")["say"].startswith("Hello! I am HOROS.")
    assert english.params_for("Interaction", "Survey")["questions"][0]["buttons"] == ["yes", "no"]


def test_the_run_takes_the_command_line_language_else_the_applications():
    dialog = load_folder("guide").dialog
    chosen, tag = language_for_run(dialog, None)
    assert tag == "en" and chosen.language == "en"
    chosen, tag = language_for_run(dialog, "de")
    assert tag == "de" and chosen.params_for("AskRoom", "Ask")["questions"][0]["buttons"][3] == \
        "Raum S1 (Seminarraum)"
    with pytest.raises(ApplicationError, match=r"texts are in English \(en\), German \(de\) only"):
        language_for_run(dialog, "fr")
    with pytest.raises(ApplicationError, match="'klingon' is not a language"):
        language_for_run(dialog, "klingon")


@pytest.mark.parametrize("app", BUNDLED)
def test_every_bundled_application_speaks_english_and_german(app):
    loaded = load_folder(app)
    assert loaded.dialog.languages == ("en", "de")
    german = loaded.dialog.in_language("de")
    for question in german.questions:
        english = next(q for q in loaded.dialog.questions if q["id"] == question["id"])
        assert question["values"] == english["values"]
        assert question["text"] != english["text"]


def test_looked_up_texts_come_from_the_languages_column():
    loaded = load_folder("receptionist")
    german = loaded.dialog.in_language("de")
    lookup = translated_lookup(loaded.content.lookup, german, loaded.content.columns)
    assert lookup("rooms", "directions", "N2").startswith("Professor Gross ist in Raum N2")
    assert lookup("rooms", "place", "N2") == "room_n2"        # not a text: no place_de column
    assert translated_lookup(loaded.content.lookup, loaded.dialog.in_language("en"),
                             loaded.content.columns)(
        "rooms", "directions", "N2").startswith("Professor Gross is in room N2")


def test_a_missing_german_column_is_reported_by_the_checker(tmp_path):
    folder = tmp_path / "receptionist"
    shutil.copytree(find_application("receptionist"), folder)
    sql = folder / "database.sql"
    sql.write_text(sql.read_text().replace("directions_de", "directions_fr"))
    found = [str(d) for d in inspect_folder(folder)[2] if d.is_error]
    assert any("graph.xml:" in line and "add a column directions_de to table rooms" in line
               for line in found), found
    labels = folder / "database.sql"
    labels.write_text(labels.read_text().replace("label_de", "label_fr"))
    found = [str(d) for d in inspect_folder(folder)[2] if d.is_error]
    assert any("dialog.xml:" in line and "add a column label_de to table rooms" in line
               for line in found), found


def test_language_klingon_in_a_bundled_copy_fails_the_check(tmp_path, capsys):
    folder = tmp_path / "survey"
    shutil.copytree(find_application("survey"), folder)
    dialog = folder / "dialog.xml"
    dialog.write_text(dialog.read_text().replace('language="en" languages="en de"',
                                                 'language="klingon" languages="en de"'))
    assert main(["check", str(folder)]) == 1
    assert "'klingon' is not a language" in capsys.readouterr().out


def test_run_in_german_speaks_and_shows_german_and_records_the_values(tmp_path, capsys):
    trace = tmp_path / "trace.jsonl"
    assert main(["run", "survey", "--language", "de", "--fast", "--scenario", "complete",
                 "--duration", "60", "--quiet", "--data", str(tmp_path),
                 "--trace", str(trace)]) == 0
    import json
    events = [json.loads(line) for line in trace.read_text().splitlines()]
    asked = [e for e in events if e["kind"] == "ask"]
    answers = [e["answer"] for e in events if e["kind"] == "answer"]
    said = [e["text"] for e in events if e["kind"] == "say"]
    assert asked[0]["buttons"] == ["ja", "nein"]
    assert answers == ["yes", "3", "no"]
    assert "Vielen Dank. Einen schönen Tag noch!" in said


def test_run_refuses_a_language_the_application_lacks(tmp_path, capsys):
    assert main(["run", "survey", "--language", "fr", "--fast", "--duration", "1",
                 "--data", str(tmp_path)]) == 2                # a mistaken argument
    assert "texts are in English (en), German (de) only" in capsys.readouterr().err
