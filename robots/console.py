"""A speaker for robots whose text-to-speech is not wired up: it only records what was said.

The skill layer prints and logs every utterance anyway; this keeps the Speaker contract.
"""
from __future__ import annotations

from robots.devices import Speaker


class ConsoleSpeaker(Speaker):
    SECONDS_PER_CHARACTER = 0.06

    def __init__(self, clock) -> None:
        self.clock = clock
        self.said: list[tuple[float, str]] = []
        self._busy_until = 0.0

    def say(self, text: str) -> None:
        now = self.clock.now()
        self.said.append((now, text))
        self._busy_until = now + self.SECONDS_PER_CHARACTER * len(text)

    def busy(self) -> bool:
        return self.clock.now() < self._busy_until
