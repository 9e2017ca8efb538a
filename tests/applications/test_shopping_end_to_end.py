"""The shopping assistant, end to end in the simulated store: the same files on PERSES and
HOROS, every bundled scenario, the searches logged, the customer followed, found again, and
given up on with a reason."""
from __future__ import annotations

from pathlib import Path

import pytest

START = ["Wait", "Attract", "AskWhat"]
END = ["AskMore", "Goodbye", "GoHome", "Wait"]
EXPECTED = {
    "product": START + ["AskProduct", "Confirm", "GuideToProduct"] + END,
    "follow_me": START + ["Follow"] + END,
    "hidden": START + ["Follow"] + END,
    "walks_off": START + ["Follow", "GiveUp", "GoHome", "Wait"],
    "nobody": ["Wait"],
}
# follow_me (200 s of robot time) runs on PERSES only here; the same following through three
# aisles runs on HOROS in tests/skills/test_following.py
RUNS = [(s, "perses") for s in sorted(EXPECTED)] + [(s, "horos") for s in sorted(EXPECTED)
                                                     if s != "follow_me"]


def run(app_runs, scenario: str, robot: str):
    """The run shared with the other tests that read it (tests/applications/app_runs.py)."""
    done = app_runs.run("shopping", robot, scenario)
    answers = done.rows("shopping", "SELECT question, answer FROM answers ORDER BY id")
    searches = done.rows("shopping",
                         "SELECT question, query, outcome, found FROM searches ORDER BY id")
    return done.code, done.trace, answers, searches


def states(trace) -> list[str]:
    return [e["to"] for e in trace if e["kind"] == "transition"]


def following(trace) -> list[tuple[float, str, str]]:
    return [(e["t"], e["status"], e["reason"]) for e in trace
            if e["kind"] == "skill" and e["name"] == "following"]


@pytest.mark.slow
@pytest.mark.parametrize("scenario,robot", RUNS)
def test_every_scenario_on_both_robots(app_runs, scenario, robot):
    code, trace, answers, searches = run(app_runs, scenario, robot)
    assert code == 0
    assert states(trace) == EXPECTED[scenario]
    assert not any(e["kind"] == "fault" for e in trace)
    CHECKS.get(scenario, lambda *args: None)(trace, answers, searches)


def a_misspelt_product_is_confirmed_found_and_logged(trace, answers, searches):
    assert answers == [("what", "find"), ("product", "expresso"), ("confirm", "yes"),
                       ("more", "no")]
    assert searches == [("product", "expresso", "close", "espresso")]
    asks = {e["question"]: e for e in trace if e["kind"] == "ask"}
    assert asks["confirm"]["text"] == "Did you mean Espresso beans 1 kg?"    # the label
    assert asks["product"]["buttons"][:2] == ["Bread and bakery", "Breakfast cereals"]
    says = [e["text"] for e in trace if e["kind"] == "say"]
    assert "Please follow me, I will take you to Espresso beans 1 kg." in says
    # GuideToProduct: on arrival the robot says what and where, from the database
    assert "Espresso beans 1 kg: here in aisle A2, at eye level, for 12.99 euros." in says


def the_customer_is_followed_to_the_end(trace, answers, searches):
    assert answers == [("what", "follow"), ("more", "no")]
    assert not any(status == "failed" for _, status, _ in following(trace))


def the_hidden_customer_is_found_again_within_5_s(trace, answers, searches):
    events = following(trace)
    hidden = next(t for t, _, reason in events if reason.startswith("hidden"))
    found = next(t for t, status, reason in events
                 if t > hidden and status == "running" and not reason.startswith(("hidden",
                                                                               "searching")))
    assert found - hidden <= 5.0
    assert not any(status == "failed" for _, status, _ in events)


def a_customer_who_walks_off_is_searched_for_called_and_given_up_on(trace, answers, searches):
    events = following(trace)
    assert any(reason.startswith("searching") for _, _, reason in events)
    failed = [reason for _, status, reason in events if status == "failed"]
    assert len(failed) == 1 and failed[0].startswith("customer lost: not seen for 30 s")
    says = [e["text"] for e in trace if e["kind"] == "say"]
    assert says.count("Where are you? I cannot see you any more.") >= 2
    assert "I am sorry, I lost you. I am going back to the entrance." in says


CHECKS = {"product": a_misspelt_product_is_confirmed_found_and_logged,
          "follow_me": the_customer_is_followed_to_the_end,
          "hidden": the_hidden_customer_is_found_again_within_5_s,
          "walks_off": a_customer_who_walks_off_is_searched_for_called_and_given_up_on}


SUGGEST = Path(__file__).resolve().parent / "scenarios" / "shopping_suggest.toml"


@pytest.mark.slow
def test_a_miss_is_offered_suggestions_and_the_question_is_answered_again(app_runs):
    """"dog food": the robot says and shows the nearest labels, asks again, and the customer
    (a simulated person answering the same question a second time) types "cat food"."""
    done = app_runs.run("shopping", "perses", str(SUGGEST))
    assert done.code == 0
    assert states(done.trace) == START + ["AskProduct", "Suggest", "AskProduct",
                                          "GuideToProduct"] + END
    searches = done.rows("shopping", "SELECT query, outcome, found FROM searches ORDER BY id")
    assert searches == [("dog food", "none", None), ("cat food", "exact", "cat food")]
    says = [e["text"] for e in done.trace if e["kind"] == "say"]
    assert ("I could not find dog food. Did you mean Canned food or Cat food, 12 pouches?"
            in says)
    assert "Please follow me, I will take you to Cat food, 12 pouches." in says
    asked = [e["question"] for e in done.trace if e["kind"] == "ask"]
    assert asked.count("product") == 2
