"""py_trees leaves that start, poll and cancel skills. Macro-behaviors are built from these.

Each leaf reaches its skill through the `BehaviorContext` only when ticked, so a tree can be
built without a robot (for drawing). `terminate` cancels what `initialise` started, and only
that, so halting a tree cancels each running skill goal exactly once.
"""
from __future__ import annotations

import py_trees
from py_trees.common import Status

from behaviors.registry import BehaviorContext
from skills.motion import Goal
from skills.questionnaire import Question


class SkillLeaf(py_trees.behaviour.Behaviour):
    def __init__(self, name: str, ctx: BehaviorContext) -> None:
        super().__init__(name)
        self.ctx = ctx
        self.started = False

    @property
    def skills(self):
        return self.ctx.skills

    @property
    def now(self) -> float:
        return self.ctx.skills.now()

    def initialise(self) -> None:
        self.started = True
        self.start()

    def terminate(self, new_status: Status) -> None:
        if self.started:
            self.started = False
            self.finish(new_status)

    def start(self) -> None:
        """Start the skill goal (called once per activation)."""

    def finish(self, new_status: Status) -> None:
        """Cancel or release what `start` began (called once per activation)."""


class Say(SkillLeaf):
    """Speak a sentence; succeeds when it has been spoken."""

    def __init__(self, ctx: BehaviorContext, text: str) -> None:
        super().__init__(f"Say '{text[:24]}'", ctx)
        self.text = text

    def start(self) -> None:
        self.skills.require("speech").say(self.text, self.now)

    def update(self) -> Status:
        return Status.RUNNING if self.skills.speech.status.running else Status.SUCCESS

    def finish(self, new_status: Status) -> None:
        if new_status == Status.INVALID:
            self.skills.speech.cancel(self.now)


class Pause(SkillLeaf):
    """Succeed after `seconds` of robot time."""

    def __init__(self, ctx: BehaviorContext, seconds: float) -> None:
        super().__init__(f"Pause {seconds:g}s", ctx)
        self.seconds = seconds
        self.until = 0.0

    def start(self) -> None:
        self.until = self.now + self.seconds

    def update(self) -> Status:
        return Status.SUCCESS if self.now >= self.until else Status.RUNNING


class StandStill(SkillLeaf):
    """Keep the base still; never finishes (the state machine ends it)."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("StandStill", ctx)

    def start(self) -> None:
        self.skills.motion.cancel(self.now)

    def update(self) -> Status:
        return Status.RUNNING


class HoldStill(SkillLeaf):
    """Stop the base (drop any motion goal) and succeed at once: the start of a finite activity."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("HoldStill", ctx)

    def update(self) -> Status:
        self.skills.motion.cancel(self.now)
        return Status.SUCCESS


class ShowInfo(SkillLeaf):
    """Put a text (and a picture) on the touch screen; it stays until the behavior ends."""

    def __init__(self, ctx: BehaviorContext, text: str, picture: str | None) -> None:
        super().__init__(f"Show '{text[:24]}'", ctx)
        self.text, self.picture = text, picture

    def update(self) -> Status:
        self.skills.require("questionnaire").screen.display(self.text, self.picture)
        return Status.SUCCESS

    def finish(self, new_status: Status) -> None:
        if new_status == Status.INVALID:
            self.skills.questionnaire.screen.clear()


class LookAtUser(SkillLeaf):
    """Keep the pan-tilt head on the user; never finishes."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("LookAtUser (head)", ctx)

    def start(self) -> None:
        self.skills.require("head").look_at_user(self.now)

    def update(self) -> Status:
        return Status.RUNNING

    def finish(self, new_status: Status) -> None:
        self.skills.head.center(self.now)


class TurnToUser(SkillLeaf):
    """Keep the whole body turned towards the user; never finishes."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("TurnToUser (body)", ctx)

    def start(self) -> None:
        self.skills.motion.start(Goal("face_user"), self.now)

    def update(self) -> Status:
        return Status.RUNNING

    def finish(self, new_status: Status) -> None:
        self.skills.motion.cancel(self.now)


class ResetSurvey(SkillLeaf):
    """Forget the last person's answers, so the next person starts a fresh survey."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("ResetSurvey", ctx)

    def update(self) -> Status:
        if self.skills.questionnaire is not None:
            self.skills.questionnaire.reset(self.now)
        return Status.SUCCESS


class LoadQuestions(SkillLeaf):
    """Hand the dialog's questions to the questionnaire; `fresh` asks them again even when this
    person answered them before (a survey resumes instead)."""

    def __init__(self, ctx: BehaviorContext, questions: tuple[Question, ...],
                 fresh: bool = False) -> None:
        super().__init__(f"LoadQuestions ({len(questions)})", ctx)
        self.questions = questions
        self.fresh = fresh

    def update(self) -> Status:
        self.skills.require("questionnaire").load(self.questions, self.now, self.fresh)
        return Status.SUCCESS


class AskQuestions(SkillLeaf):
    """Ask each unanswered question in turn; succeed when all have answers."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("AskQuestions", ctx)

    def start(self) -> None:
        self._ask()

    def _ask(self) -> bool:
        question = self.skills.questionnaire.ask_next(self.now)
        if question is not None and self.skills.speech is not None:
            self.skills.speech.say(question.text, self.now)
        return question is not None

    def update(self) -> Status:
        status = self.skills.questionnaire.status
        if status.failed:
            return Status.FAILURE
        if status.running:
            return Status.RUNNING
        return Status.RUNNING if self._ask() else Status.SUCCESS

    def finish(self, new_status: Status) -> None:
        if new_status == Status.INVALID:
            self.skills.questionnaire.cancel(self.now)


class CloseSurvey(SkillLeaf):
    """Mark the survey finished once every answer is in and the thanks were said."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("CloseSurvey", ctx)

    def update(self) -> Status:
        self.skills.questionnaire.close(self.now)
        return Status.SUCCESS


class OnlyIf(py_trees.behaviour.Behaviour):
    """A guard leaf: SUCCESS when the predicate on the skills holds, else FAILURE."""

    def __init__(self, name: str, ctx: BehaviorContext, predicate) -> None:
        super().__init__(name)
        self.ctx = ctx
        self.predicate = predicate

    def update(self) -> Status:
        return Status.SUCCESS if self.predicate(self.ctx.skills) else Status.FAILURE
