"""Speech output: say a sentence through the robot's speaker; printed and logged as a `say` event."""
from __future__ import annotations

import logging

from robots.devices import Speaker
from skills.skill import Skill
from skills.status import IDLE, RUNNING, SUCCEEDED

log = logging.getLogger("interbot.speech")


class Speech(Skill):
    name = "speech"

    def __init__(self, blackboard, events, speaker: Speaker) -> None:
        super().__init__(blackboard, events)
        self.speaker = speaker

    def say(self, text: str, now: float) -> None:
        self.speaker.say(text)
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
