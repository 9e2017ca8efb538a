"""Ask: ask questions on the touch screen (and aloud) while facing the user; done when all are
answered. Unlike Survey, it asks afresh each time its state is entered, and does not close a
survey: its answers are read in conditions as `answer.<id>` and `dialog.answer`."""
from __future__ import annotations

import py_trees

from behaviors.leaves import AskQuestions, HoldStill, LoadQuestions, Say
from behaviors.library.common import facing_user_until_done, head_and_body
from behaviors.library.survey import questions_from
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec


def build(ctx: BehaviorContext, with_head: bool):
    steps = [HoldStill(ctx), LoadQuestions(ctx, questions_from(ctx.params), fresh=True)]
    if ctx.param("say", None):
        steps.append(Say(ctx, ctx.params["say"]))
    steps.append(AskQuestions(ctx))
    if ctx.param("closing", None):
        steps.append(Say(ctx, ctx.params["closing"]))
    asking = py_trees.composites.Sequence("Ask", memory=True, children=steps)
    return facing_user_until_done("Ask", ctx, with_head, asking)


ASK = BehaviorSpec(
    name="Ask",
    description="Ask questions on the touch screen and aloud; done when all are answered.",
    realizations=head_and_body(frozenset({"touch_screen", "speech_out"}), build),
    parameters={"say": ParameterSpec("text", "said before the first question"),
                "questions": ParameterSpec("questions", "the questions with their answers",
                                           required=True),
                "closing": ParameterSpec("text", "said after the last answer")},
    records_answers=True,
)
