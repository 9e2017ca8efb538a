"""What simulated people make of the robot's words. Most of what it says counts alike (a call,
an ask to wait: any utterance, `robots.sim.heeding`, `robots.sim.visitors`); asking people in
the way to let it pass is told apart by its words, as people tell it apart, so a customer
leading the robot does not take it for "wait for me" and a shopper in its lane steps aside
(`robots.sim.letting_pass`). English words only: a robot that asks in other words is not
understood as asking to pass."""
from __future__ import annotations

ASKING_TO_PASS = ("excuse me", "pass", "make way", "let me through")


def asks_to_pass(text: str) -> bool:
    """Whether an utterance asks people in the way to let the robot pass."""
    words = text.lower()
    return any(phrase in words for phrase in ASKING_TO_PASS)
