"""Survey: ask the dialog's questions on the touch screen while facing the user.

Answers are kept by the questionnaire skill, so a user who is called back resumes at the
first unanswered question; the introduction is only said to someone who has answered nothing.
"""
from __future__ import annotations

import py_trees

from behaviors.leaves import AskQuestions, CloseSurvey, LoadQuestions, OnlyIf, Say
from behaviors.library.common import head_and_body, while_facing_user
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec
from skills.questionnaire import Question

INTRO = "Thank you for taking part in our survey."
THANKS = "Thank you very much. Have a nice day!"


def questions_from(params: dict) -> tuple[Question, ...]:
    """The questions of the `questions` parameter (dicts as the application's dialog gives them)."""
    return tuple(Question(str(q["id"]), str(q["text"]), tuple(str(b) for b in q["buttons"]),
                          tuple(str(v) for v in q.get("values", ())), bool(q.get("typed")),
                          tuple((str(k), str(v)) for k, v in q.get("aliases", {}).items()))
                 for q in params.get("questions", ()))


def _nothing_answered(skills) -> bool:
    return not skills.questionnaire.answers


def build(ctx: BehaviorContext, with_head: bool):
    intro = py_trees.composites.Selector("Introduce once", memory=True, children=[
        py_trees.decorators.Inverter("Answered some", OnlyIf("Nothing answered", ctx, _nothing_answered)),
        Say(ctx, ctx.param("say", INTRO)),
    ])
    dialog = py_trees.composites.Sequence("Questionnaire", memory=True, children=[
        LoadQuestions(ctx, questions_from(ctx.params)),
        intro,
        AskQuestions(ctx),
        Say(ctx, ctx.param("closing", THANKS)),
        CloseSurvey(ctx),
    ])
    return while_facing_user("Survey", ctx, with_head, dialog)


SURVEY = BehaviorSpec(
    name="Survey",
    description="Ask the survey questions on the touch screen while facing the user.",
    realizations=head_and_body(frozenset({"touch_screen", "speech_out"}), build),
    parameters={"say": ParameterSpec("text", "the introduction, said once to a new user"),
                "questions": ParameterSpec("questions", "the questions with their answers",
                                           required=True),
                "closing": ParameterSpec("text", "the thanks at the end")},
    records_answers=True,
)
