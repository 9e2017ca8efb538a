"""Speech out through espeak-ng and spoken answers through pocketsphinx, on WAV files that
espeak-ng itself speaks (the test has no microphone and no sound card)."""
from __future__ import annotations

import subprocess
import wave

import pytest

from robots.audio.espeak import EspeakSpeaker, espeak_voices, wav_duration
from robots.audio.recognizer import AnswerRecognizer, spoken_forms
from robots.audio.source import MicrophoneSource, WavFileSource
from robots.clock import RealClock
from robots.exceptions import RobotError


def spoken(tmp_path, text: str, voice: str = "en-us"):
    path = tmp_path / f"{text.replace(' ', '_')}.wav"
    subprocess.run(["espeak-ng", "-v", voice, "-w", str(path), text], check=True)
    return path


def hear(path, choices, prompt="q1"):
    recognizer = AnswerRecognizer(WavFileSource(path))
    recognizer.listen(prompt, choices)
    recognizer.wait(60.0)
    heard = recognizer.take_heard()
    recognizer.close()
    return heard, recognizer.rejected


def test_yes_is_recognised_among_yes_and_no(tmp_path):
    heard, _ = hear(spoken(tmp_path, "yes"), ("yes", "no"))
    assert heard == ("q1", "yes")


def test_a_word_that_is_not_an_answer_is_rejected(tmp_path):
    heard, rejected = hear(spoken(tmp_path, "banana"), ("yes", "no"))
    assert heard is None and len(rejected) == 1


def test_a_number_button_is_heard_as_its_word(tmp_path):
    assert spoken_forms("3") == "three" and spoken_forms("Yes, please!") == "yes please"
    heard, _ = hear(spoken(tmp_path, "three"), ("1", "2", "3", "4", "5"), prompt="q2")
    assert heard == ("q2", "3")


def test_only_english_can_be_recognised():
    with pytest.raises(RobotError, match="English model only"):
        AnswerRecognizer(WavFileSource.__new__(WavFileSource), language="de")


def test_a_missing_capture_device_is_a_clear_error():
    with pytest.raises(RobotError, match="no microphone"):
        MicrophoneSource(device="hw:interbot_no_such_card")


def test_speech_goes_to_numbered_wav_files_and_is_busy_while_it_lasts(tmp_path):
    clock = RealClock()
    speaker = EspeakSpeaker(clock, "en", wav_dir=tmp_path)
    speaker.say("Hello! I am HOROS.")
    assert speaker.busy()
    while speaker.busy():
        clock.sleep_until(clock.now() + 0.02)
    speaker.say("Danke schön.")
    speaker.close()
    first = tmp_path / "0001.wav"
    assert (tmp_path / "0001.txt").read_text() == "Hello! I am HOROS.\n"
    assert (tmp_path / "0002.txt").read_text() == "Danke schön.\n"
    with wave.open(str(first)) as wav:
        assert wav.getnframes() > 0.5 * wav.getframerate()
    assert wav_duration(first) > 0.5


def test_german_and_english_voices_exist_and_an_unknown_language_is_refused(tmp_path):
    assert espeak_voices("de") and espeak_voices("en")
    speaker = EspeakSpeaker(RealClock(), "de", wav_dir=tmp_path)
    speaker.say("Guten Tag")
    speaker.close()
    with pytest.raises(RobotError, match="no voice for language 'xx'"):
        EspeakSpeaker(RealClock(), "xx")
