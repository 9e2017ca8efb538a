"""Speech output: say a sentence through the robot's speaker; printed and logged as a `say` event,
and shown as a caption on the touch screen where there is one (for people who cannot hear it)."""
from __future__ import annotations

import logging

from robots.devices import Speaker, TouchScreen
from skills.skill import Skill
from skills.status import IDLE, RUNNING, SUCCEEDED

log = logging.getLogger("interbot.speech")


class Speech(Skill):
    name = "speech"

    def __init__(self, blackboard, events, speaker: Speaker,
                 screen: TouchScreen | None = None) -> None:
        super().__init__(blackboard, events)
        self.speaker = speaker
        self.screen = screen

    def say(self, text: str, now: float) -> None:
        self.speaker.say(text)
        if self.screen is not None:
            self.screen.caption(text)
        log.info("say: %s", text)
        self.events.emit(now, "say", text=text)
        self.write("speech/last", text, now)
        self.set_status(RUNNING, now)

    def cancel(self, now: float) -> None:
        self.set_status(IDLE, now)

    def sense(self, now: float) -> None:
        busy = self.speaker.busy()
        self.write("speech/busy", busy, now)
        if self.status.running and not busy:
            self.set_status(SUCCEEDED, now)
