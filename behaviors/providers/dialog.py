"""The dialog percepts: the survey's progress and the answers people gave on the touch screen.

`answer.<question id>` exists for every question of the application; its declaration (with the
question's possible answers as values) is made by L3 from the application's dialog, because only
the application knows its questions. This provider reads the values for whichever ids have one.
"""
from __future__ import annotations

from behaviors.percepts import PerceptContext, PerceptProvider, spec

ANSWER_PREFIX = "answer."

SPECS = (
    spec("survey.done", "bool", doc="every question of the active question set has an answer"),
    spec("survey.answered", "int", None, (0, 1000), "questions answered so far in this session"),
    spec("dialog.answer", "str",
         doc="the last answer given in this session (a value of the question's answers); "
             "absent before the first answer"),
    spec("dialog.asking", "str", doc="the id of the question on the screen now; absent when none"),
)


def read(ctx: PerceptContext) -> dict:
    progress = ctx.skills.blackboard.value("survey/progress")
    values = {
        "survey.done": bool(progress and progress.closed),
        "survey.answered": progress.answered if progress else 0,
        "dialog.answer": progress.last[1] if progress and progress.last else None,
        "dialog.asking": progress.asking if progress else None,
    }
    for question, answer in (progress.answers if progress else ()):
        values[ANSWER_PREFIX + question] = answer
    return values


DIALOG = PerceptProvider("dialog", SPECS, read, needs=frozenset({"touch_screen"}))
