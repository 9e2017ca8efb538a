"""The questionnaire: ask survey questions on the touch screen and collect the answers.

An answer is a press on the screen (`touch` on a tablet, `sim` from a simulated person) or, where
the robot listens, one of the buttons said aloud (`voice`); the `answer` event names its source.

Progress outlives any one behavior tree, so a user who is called back continues where they
stopped; `reset` starts a fresh session for the next person.
"""
from __future__ import annotations

from dataclasses import dataclass

from robots.devices import SpeechRecognizer, TouchScreen
from skills.skill import Skill
from skills.status import IDLE, RUNNING, SUCCEEDED


@dataclass(frozen=True)
class Question:
    """A question: its id, text, the button labels, the value each button records (the label
    itself where no value is given) and whether typed text is also an answer."""
    id: str
    text: str
    buttons: tuple[str, ...]
    values: tuple[str, ...] = ()
    typed: bool = False
    aliases: tuple[tuple[str, str], ...] = ()   # (label in another language, value)

    def value_of(self, given: str) -> str | None:
        """The answer a press or typed text means, or None when it is no answer to this question."""
        if given in self.buttons:
            index = self.buttons.index(given)
            return self.values[index] if index < len(self.values) and self.values[index] else given
        for label, value in self.aliases:
            if given == label:           # the same button in another of the application's languages
                return value
        if self.typed and given.strip():
            return " ".join(given.split())
        return None


@dataclass(frozen=True)
class SurveyProgress:
    answers: tuple[tuple[str, str], ...]   # (question id, answer) in the order given
    total: int
    asking: str | None = None
    closed: bool = False                   # the session was closed (thanks said) after the last answer
    last: tuple[str, str] | None = None    # the newest (question id, answer) of the session
    pending: int = 0                       # questions of the current set still unanswered

    @property
    def answered(self) -> int:
        return len(self.answers)

    @property
    def done(self) -> bool:
        return self.total > 0 and self.pending == 0


class Questionnaire(Skill):
    name = "questionnaire"

    def __init__(self, blackboard, events, screen: TouchScreen,
                 recognizer: SpeechRecognizer | None = None) -> None:
        super().__init__(blackboard, events)
        self.screen = screen
        self.recognizer = recognizer
        self.questions: tuple[Question, ...] = ()
        self.answers: dict[str, str] = {}
        self.asking: Question | None = None
        self.closed = False
        self.last: tuple[str, str] | None = None
        self.session = 0

    def load(self, questions: tuple[Question, ...], now: float, fresh: bool = False) -> None:
        """Ask these questions next. Answers of the session are kept (a called-back user
        resumes, a later state can read an earlier answer); `fresh` forgets the answers to
        these questions, so they are asked again."""
        if questions != self.questions:
            self.questions = questions
            self.closed = False
        if fresh:
            for question in questions:
                self.answers.pop(question.id, None)
            self.closed = False
        self.cancel(now)

    def reset(self, now: float) -> None:
        """A new person: forget every answer and start a new session."""
        self.answers = {}
        self.last = None
        self.closed = False
        self.session += 1
        self.cancel(now)

    def close(self, now: float) -> None:
        """The survey with this person is over (every answer given and the thanks said)."""
        self.closed = self.progress().done
        self._publish(now)

    def next_question(self) -> Question | None:
        return next((q for q in self.questions if q.id not in self.answers), None)

    def ask_next(self, now: float) -> Question | None:
        question = self.next_question()
        if question is None:
            self.set_status(SUCCEEDED, now)
            return None
        self.asking = question
        self.screen.show(question.id, question.text, question.buttons, question.typed)
        if self.recognizer is not None:
            self.recognizer.listen(question.id, question.buttons)
        self.events.emit(now, "ask", question=question.id, text=question.text,
                         buttons=list(question.buttons))
        self.set_status(RUNNING, now)
        return question

    def cancel(self, now: float) -> None:
        self.asking = None
        self.screen.clear()
        self._stop_listening()
        self.set_status(IDLE, now)
        self._publish(now)

    def sense(self, now: float) -> None:
        press = self.screen.take_press_from()
        while press is not None:
            self._record(press, now)
            press = self.screen.take_press_from()
        if self.recognizer is not None:
            heard = self.recognizer.take_heard()
            while heard is not None:
                self._record((heard[0], heard[1], "voice"), now)
                heard = self.recognizer.take_heard()
        self._publish(now)

    def _record(self, press: tuple[str, str, str], now: float) -> None:
        prompt_id, given, source = press
        if self.asking is None or prompt_id != self.asking.id:
            return   # a stale press, or one for a prompt no longer shown: ignore it
        answer = self.asking.value_of(given)
        if answer is None:
            return   # not one of the answers on the screen
        self.answers[prompt_id] = answer
        self.last = (prompt_id, answer)
        self.events.emit(now, "answer", question=prompt_id, answer=answer, session=self.session,
                         source=source)
        self.asking = None
        self.screen.clear()
        self._stop_listening()
        self.set_status(SUCCEEDED, now)

    def _stop_listening(self) -> None:
        if self.recognizer is not None:
            self.recognizer.stop()

    def progress(self) -> SurveyProgress:
        return SurveyProgress(tuple(self.answers.items()), len(self.questions),
                              self.asking.id if self.asking else None, self.closed, self.last,
                              sum(1 for q in self.questions if q.id not in self.answers))

    def _publish(self, now: float) -> None:
        self.write("survey/progress", self.progress(), now)
