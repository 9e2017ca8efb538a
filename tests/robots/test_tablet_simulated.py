"""The tablet on its wire in simulation: what the robot shows reaches the world's glass through
the page's WebSocket, and what a simulated person presses reaches the robot the same way,
checked by the page as a browser's press is."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from robots.sim.world import ScreenState
from robots.tablet.simulated import WiredTouchScreen


@pytest.fixture
def wired():
    world = SimpleNamespace(screen=ScreenState(), t=12.5)
    screen = WiredTouchScreen.for_world(world)
    yield screen, world
    screen.close()


def test_a_question_reaches_the_glass_and_a_press_comes_back_through_the_page(wired):
    screen, world = wired
    screen.show("q1", "Do you like it here?", ("yes", "no"))
    assert world.screen.prompt == ("q1", "Do you like it here?", ("yes", "no"))
    assert world.screen.shown_at == 12.5
    world.screen.press("q1", "yes")
    assert screen.take_press() == ("q1", "yes")
    assert screen.take_press() is None
    assert screen.tablet.replies[-1]["type"] == "accepted"


def test_a_press_the_page_refuses_never_reaches_the_robot(wired):
    screen, world = wired
    screen.show("q1", "Do you like it here?", ("yes", "no"))
    world.screen.press("q1", "maybe")                  # not one of the answers
    world.screen.press("q0", "yes")                    # a question no longer shown
    assert screen.take_press() is None
    assert [reply["type"] for reply in screen.tablet.replies] == ["refused", "refused"]


def test_info_caption_and_clear_reach_the_glass(wired):
    screen, world = wired
    screen.display("Room N2 is down the hall")
    screen.caption("Follow me, please")
    assert world.screen.info == ("Room N2 is down the hall", None)
    assert world.screen.caption == "Follow me, please"
    screen.clear()
    assert world.screen.prompt is None and world.screen.info is None
