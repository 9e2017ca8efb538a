"""The simulated robot's voice through the real speech engine (`interbot run --wire`).

What the robot says goes through espeak-ng, as on the robot, into numbered WAV files (the
simulation has no sound card), and the simulated people hear it in the world. On a simulated
clock each utterance is waited for (lock-step, as the other devices on their wires), so the
WAV's length is known before the next tick and a run stays deterministic: the robot is busy
speaking while either the world's speech model or the WAV says so.
"""
from __future__ import annotations

import shutil
import tempfile
import time
from pathlib import Path

from robots.audio.espeak import EspeakSpeaker
from robots.devices import Speaker

ENGINE_TIMEOUT = 10.0        # real s espeak-ng may take for one utterance


class WiredVoice(Speaker):
    def __init__(self, heard: Speaker, engine: EspeakSpeaker, clock,
                 own_folder: Path | None = None) -> None:
        self.heard = heard            # the world's speaker: what the simulated people hear
        self.engine = engine
        self.lockstep = bool(getattr(clock, "simulated", False))
        self._own_folder = own_folder  # a temporary WAV folder this voice removes on close

    @classmethod
    def for_world(cls, heard: Speaker, clock, language: str = "en", voice: str | None = None,
                  wav_dir: str | Path | None = None) -> "WiredVoice":
        own = None if wav_dir is not None else Path(tempfile.mkdtemp(prefix="interbot-voice-"))
        engine = EspeakSpeaker(clock, language, voice, wav_dir if wav_dir is not None else own)
        return cls(heard, engine, clock, own)

    @property
    def wav_dir(self) -> Path | None:
        return self.engine.wav_dir

    def say(self, text: str) -> None:
        self.heard.say(text)
        self.engine.say(text)
        if self.lockstep:
            self._wait_for_engine()

    def _wait_for_engine(self) -> None:
        deadline = time.monotonic() + ENGINE_TIMEOUT
        while self.engine.busy_rendering() and time.monotonic() < deadline:
            time.sleep(0.002)

    def busy(self) -> bool:
        return self.heard.busy() or self.engine.busy()

    def close(self) -> None:
        try:
            self.engine.close()
        finally:
            if self._own_folder is not None:
                shutil.rmtree(self._own_folder, ignore_errors=True)
