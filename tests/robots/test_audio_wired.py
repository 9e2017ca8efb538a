"""The simulated robot's voice on its wire: espeak-ng writes each utterance to a WAV file, the
world hears the text, and on a simulated clock the robot is busy for the WAV's length in robot
time, however long espeak-ng took in real time (lock-step)."""
from __future__ import annotations

from robots.audio.espeak import wav_duration
from robots.audio.wired import WiredVoice
from robots.clock import SimClock
from robots.devices import Speaker


class Heard(Speaker):
    """The world's side: what was said, busy for a fixed time."""

    def __init__(self, clock, seconds: float) -> None:
        self.clock, self.seconds, self.said, self.until = clock, seconds, [], 0.0

    def say(self, text: str) -> None:
        self.said.append(text)
        self.until = self.clock.now() + self.seconds

    def busy(self) -> bool:
        return self.clock.now() < self.until


def test_the_voice_is_a_wav_the_world_hears_and_busy_for_its_length(tmp_path):
    clock = SimClock()
    heard = Heard(clock, 0.1)
    voice = WiredVoice.for_world(heard, clock, wav_dir=tmp_path)
    try:
        voice.say("Hello there, please answer on my screen.")
        wav = tmp_path / "0001.wav"
        assert heard.said == ["Hello there, please answer on my screen."]
        assert wav.is_file() and (tmp_path / "0001.txt").read_text().startswith("Hello there")
        length = wav_duration(wav)
        assert length > 1.0                         # a sentence: well over the world's 0.1 s
        clock.advance(length - 0.05)
        assert voice.busy()
        clock.advance(0.1)
        assert not voice.busy()
    finally:
        voice.close()


def test_without_a_folder_the_wavs_go_to_one_that_is_removed_at_the_end():
    clock = SimClock()
    voice = WiredVoice.for_world(Heard(clock, 0.0), clock)
    folder = voice.wav_dir
    voice.say("Goodbye.")
    assert (folder / "0001.wav").is_file()
    voice.close()
    assert not folder.exists()
