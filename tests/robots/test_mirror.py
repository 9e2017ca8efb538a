"""A screen shown on the simulated glass and the tablet page at once; a voice through two
speakers: the simulated people keep working beside a person at the page."""
from __future__ import annotations

from robots.mirror import MirroredSpeaker, MirroredTouchScreen
from robots.sim.devices import SimSpeaker, SimTouchScreen
from robots.sim.floor import load_floor
from robots.profile import load_profile
from robots.sim.world import World
from robots.tablet.screen import ScreenContent
from robots.devices import TouchScreen


class PageScreen(TouchScreen):
    """The tablet's screen model without its server (the server has its own tests)."""

    def __init__(self):
        self.content = ScreenContent()

    def show(self, prompt_id, text, buttons, typed=False):
        self.content.show(prompt_id, text, tuple(buttons), typed)

    def caption(self, text):
        self.content.caption(text)

    def clear(self):
        self.content.clear()

    def take_press(self):
        return self.content.take_press()


def world():
    return World(load_floor("office"), load_profile("horos"))


def test_both_screens_show_and_a_press_on_either_counts_with_its_source():
    w = world()
    sim, page = SimTouchScreen(w), PageScreen()
    screen = MirroredTouchScreen(sim, page)
    screen.show("q1", "Coffee?", ("yes", "no"))
    screen.caption("Coffee?")
    assert w.screen.prompt == ("q1", "Coffee?", ("yes", "no"))
    assert page.content.snapshot()["buttons"] == ["yes", "no"]
    assert page.content.snapshot()["caption"] == w.screen.caption == "Coffee?"
    assert page.content.press("q1", "no") is None
    w.screen.press("q1", "yes")
    assert screen.take_press_from() == ("q1", "yes", "sim")
    assert screen.take_press_from() == ("q1", "no", "touch")
    assert screen.take_press() is None
    screen.clear()
    assert w.screen.prompt is None and page.content.snapshot()["mode"] == "idle"


def test_a_mirrored_speaker_says_everything_everywhere_and_is_busy_while_any_is():
    w = world()

    class Slow(SimSpeaker):
        said = []

        def say(self, text):
            self.said.append(text)

        def busy(self):
            return bool(self.said)

    slow = Slow(w)
    speaker = MirroredSpeaker(SimSpeaker(w), slow)
    speaker.say("Hello")
    assert [text for _, text in w.utterances] == ["Hello"] and slow.said == ["Hello"]
    assert speaker.busy()
    slow.said.clear()
    w.t = 100.0
    assert not speaker.busy()
