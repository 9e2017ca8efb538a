from robots.devices import TouchScreen
from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.questionnaire import Question, Questionnaire

QUESTIONS = (Question("q1", "Coffee?", ("yes", "no")), Question("q2", "Rate", ("1", "2", "3")))


class FakeScreen(TouchScreen):
    def __init__(self):
        self.shown = None
        self.presses = []

    def show(self, prompt_id, text, buttons, typed=False):
        self.shown = (prompt_id, text, buttons)

    def clear(self):
        self.shown = None

    def take_press(self):
        return self.presses.pop(0) if self.presses else None


def make():
    screen, events = FakeScreen(), EventLog()
    skill = Questionnaire(Blackboard("test"), events, screen)
    skill.load(QUESTIONS, 0.0)
    return skill, screen, events


def test_asks_in_order_and_records_each_answer_as_an_event():
    skill, screen, events = make()
    assert skill.ask_next(1.0).id == "q1"
    assert screen.shown == ("q1", "Coffee?", ("yes", "no"))
    screen.presses.append(("q1", "yes"))
    skill.sense(2.0)
    assert skill.status.succeeded and screen.shown is None
    answers = [e for e in events.drain() if e.kind == "answer"]
    assert [(e.fields["question"], e.fields["answer"]) for e in answers] == [("q1", "yes")]
    assert skill.next_question().id == "q2"


def test_a_press_for_another_prompt_or_an_unknown_button_is_ignored():
    skill, screen, _ = make()
    skill.ask_next(0.0)
    screen.presses += [("q2", "1"), ("q1", "maybe")]
    skill.sense(1.0)
    assert skill.answers == {} and skill.status.running


def test_progress_survives_a_cancel_and_the_session_closes_when_done():
    skill, screen, _ = make()
    skill.ask_next(0.0)
    screen.presses.append(("q1", "no"))
    skill.sense(1.0)
    skill.cancel(2.0)                      # the user walked away
    assert skill.ask_next(3.0).id == "q2"  # called back: resumes
    screen.presses.append(("q2", "3"))
    skill.sense(4.0)
    skill.close(5.0)
    progress = skill.blackboard.read("survey/progress").value
    assert progress.done and progress.closed and progress.answers == (("q1", "no"), ("q2", "3"))


def test_reset_starts_a_new_session():
    skill, screen, _ = make()
    skill.ask_next(0.0)
    screen.presses.append(("q1", "no"))
    skill.sense(1.0)
    session = skill.session
    skill.reset(2.0)
    assert skill.answers == {} and skill.session == session + 1 and not skill.closed


class FakeRecognizer:
    def __init__(self):
        self.choices = None
        self.heard = []

    def listen(self, prompt_id, choices):
        self.choices = (prompt_id, tuple(choices))

    def stop(self):
        self.choices = None

    def take_heard(self):
        return self.heard.pop(0) if self.heard else None


def test_a_spoken_answer_counts_like_a_press_and_says_where_it_came_from():
    screen, events, ears = FakeScreen(), EventLog(), FakeRecognizer()
    skill = Questionnaire(Blackboard("test"), events, screen, ears)
    skill.load(QUESTIONS, 0.0)
    skill.ask_next(1.0)
    assert ears.choices == ("q1", ("yes", "no"))      # listens for the buttons on screen
    ears.heard.append(("q1", "no"))
    skill.sense(2.0)
    assert skill.answers == {"q1": "no"} and ears.choices is None and screen.shown is None
    skill.ask_next(3.0)
    screen.presses.append(("q2", "2"))
    ears.heard.append(("q2", "3"))                   # too late: the press came first
    skill.sense(4.0)
    answers = [e.fields for e in events.drain() if e.kind == "answer"]
    assert [(a["question"], a["answer"], a["source"]) for a in answers] == [
        ("q1", "no", "voice"), ("q2", "2", "touch")]


def test_yes_said_aloud_answers_the_question_on_screen(tmp_path):
    import subprocess

    from robots.audio.recognizer import AnswerRecognizer
    from robots.audio.source import WavFileSource

    said = tmp_path / "yes.wav"
    subprocess.run(["espeak-ng", "-v", "en-us", "-w", str(said), "yes"], check=True)
    ears = AnswerRecognizer(WavFileSource(said))
    screen, events = FakeScreen(), EventLog()
    skill = Questionnaire(Blackboard("test"), events, screen, ears)
    skill.load(QUESTIONS, 0.0)
    skill.ask_next(1.0)                 # shows q1 and starts listening for yes / no
    ears.wait(60.0)                     # the file has been heard to its end
    skill.sense(2.0)
    ears.close()
    answers = [e.fields for e in events.drain() if e.kind == "answer"]
    assert [(a["question"], a["answer"], a["source"]) for a in answers] == [("q1", "yes", "voice")]


def test_a_button_named_in_another_language_answers_with_its_value():
    german = Question("q1", "Kaffee?", ("ja", "nein"), ("yes", "no"),
                      aliases=(("yes", "yes"), ("no", "no")))
    assert german.value_of("ja") == "yes"
    assert german.value_of("no") == "no"          # a scenario written in English still answers
    assert german.value_of("maybe") is None
