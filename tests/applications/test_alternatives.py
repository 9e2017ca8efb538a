"""Choice points in dialog.xml (issue 27, point 1): the checker, and choosing in a run."""
import json

from applications.alternatives import parse_duration
from applications.appfolder import inspect_folder, load_folder
from applications.cli import main
from applications.learning.chooser import Chooser, LearnerOptions, context_key
from tests.applications.learning_app import survey_with_choice

BAD = """<choice id="bad" state="CreateAtention" by="lern" context="user.distance, nope">
    <alternative id="x" behavior="FaceUser"><param name="sey" value="1"/></alternative>
    <alternative id="x" behavior="Nope"/>
    <success when='state == "Interacton"'/>
  </choice>
  <choice id="attract" state="CreateAttention">
    <alternative id="only"/>
  </choice>"""


def test_the_checker_reports_each_problem_of_a_choice_with_its_place_and_a_fix(tmp_path):
    folder = survey_with_choice(tmp_path / "app", choice=BAD)
    _, loaded, found = inspect_folder(folder)
    assert loaded is None
    lines = [str(d) for d in found]
    dialog = folder / "dialog.xml"
    text = dialog.read_text().splitlines()
    line = next(i for i, l in enumerate(text, 1) if 'id="bad"' in l)

    def at(row: int, needle: str) -> str:
        return f"{dialog}:{row}:{text[row - 1].index(needle) + 1}:"

    expected = [
        (at(line, "CreateAtention"), "unknown state 'CreateAtention' (did you mean 'CreateAttention'?)"),
        (at(line, "lern"), "unknown choice by=\"lern\" (did you mean 'learn'?)"),
        (at(line, "user.distance"), "context percept 'user.distance' is a float"),
        (at(line, "nope"), "unknown percept 'nope' in context"),
        (at(line + 1, "sey"), "takes no parameter 'sey' (did you mean 'say'?)"),
        (at(line + 2, "x\""), "alternative id 'x' is used twice"),
        (at(line + 2, "Nope"), "unknown behavior 'Nope'"),
        (at(line + 3, "<success"), "needs within=\"…\""),
        (at(line + 3, '"Interacton"'), "'state' is never 'Interacton' (did you mean 'Interaction'?)"),
        (at(line + 5, "<choice"), "needs by=\"…\""),
        (at(line + 5, "<choice"), "warning: <choice> offers a single <alternative>"),
    ]
    for where, what in expected:
        assert any(l.startswith(where) and what in l for l in lines), (where, what, lines)


def test_a_good_choice_point_is_read_with_its_alternatives_and_success(tmp_path):
    folder = survey_with_choice(tmp_path / "app", context="people.count")
    loaded = load_folder(folder)
    (point,) = loaded.dialog.choices
    assert (point.id, point.state, point.by, point.ids) == ("attract", "CreateAttention",
                                                            "learn", ("face", "call"))
    assert point.alternative("call").params["say"] == "Hi! Over here, please!"
    assert "Please come closer" in loaded.dialog.params_for("CreateAttention", "FaceUser")["say"]
    assert point.success.within == 15.0 and point.context == ("people.count",)


def test_check_command_prints_choice_problems(tmp_path, capsys):
    folder = survey_with_choice(tmp_path / "app", by="best")
    assert main(["check", str(folder), "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    (problem,) = [d for d in report["diagnostics"] if d["code"] == "choice-by"]
    assert problem["line"] > 1 and "allowed: first, random, rotate, learn" in problem["message"]


def test_durations():
    assert parse_duration("15s") == 15.0 and parse_duration("2 min") == 120.0
    assert parse_duration("500ms") == 0.5 and parse_duration("fast") is None


class _Percepts(dict):
    pass


def _chooser(tmp_path, by, **options):
    folder = survey_with_choice(tmp_path / "app", by=by, context="people.count")
    events = []
    chooser = Chooser(load_folder(folder).dialog.choices, None, LearnerOptions(**options),
                      emit=events.append)
    return chooser, events


def test_first_and_rotate_choose_as_they_say(tmp_path):
    chooser, _ = _chooser(tmp_path, "first")
    assert [chooser.pick("CreateAttention", {}, t).id for t in range(3)] == ["face"] * 3
    assert chooser.pick("Wait", {}, 4.0) is None
    chooser.options = LearnerOptions(strategy="rotate")
    assert [chooser.pick("CreateAttention", {}, t).id for t in range(4)] == [
        "face", "call", "face", "call"]


def test_an_episode_succeeds_when_its_condition_holds_and_fails_after_the_time_limit(tmp_path):
    chooser, events = _chooser(tmp_path, "first")
    chooser.pick("CreateAttention", {"people.count": 5}, 10.0)
    chooser.watch("CreateAttention", {}, 12.0)
    chooser.watch("Interaction", {}, 13.0)
    chooser.pick("CreateAttention", {"people.count": 1}, 20.0)
    chooser.watch("CreateAttention", {}, 34.9)
    assert [e["kind"] for e in events] == ["choice", "outcome", "choice"]
    chooser.watch("CreateAttention", {}, 35.0)
    outcomes = [e for e in events if e["kind"] == "outcome"]
    assert [(o["success"], o["after"], o["context"]) for o in outcomes] == [
        (True, 3.0, "people.count=3+"), (False, 15.0, "people.count=1")]


def test_context_keys():
    assert context_key(("people.count", "user.present"), {"people.count": 2}) == (
        "people.count=2,user.present=absent")
    assert context_key((), {"people.count": 2}) == ""


def test_an_alternative_says_its_text_in_the_run_s_language(tmp_path):
    """The survey speaks English and German: a choice's alternatives carry both texts, and a
    German run's choice point says the German one."""
    loaded = load_folder(survey_with_choice(tmp_path / "app"))
    english, german = (loaded.dialog.in_language(language).choices[0].alternative("call")
                       for language in ("en", "de"))
    assert english.params["say"] == "Hi! Over here, please!"
    assert german.params["say"] == "Hallo! Hier herüber, bitte!"
