"""Spoken answers: how many of each bundled application's answers the recognizer hears, and how
many other words it rejects, per application and language.

Each answer button of every question is spoken by espeak-ng in three voices of the language
(the part before brackets, for "Room S1 (seminar room)"); each must be recognised as that
button among the question's buttons (recognition rate). Ten words that are no answer are
spoken in the first voice against every question; each must be rejected (rejection rate).
The recognizer decodes each whole utterance with the grammar and rivals it listens with
(`AnswerRecognizer.hear_utterance`); the microphone's endpointing is not part of this.

    python benchmarks/bench_voice.py [--apps survey,guide] [--languages en,de]
                                     [--threshold -20] [--voices 3]

The engine is pocketsphinx (robots/audio/recognizer.py says why); figures in
docs/tablet-and-voice.md.

Benchmarks are not a layer: this script reads the applications (L3) and the recognizer (L0).
"""
from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from applications.appfolder import load_folder            # noqa: E402
from robots.audio.recognizer import DEFAULT_THRESHOLD, AnswerRecognizer   # noqa: E402
from robots.audio.source import WavFileSource               # noqa: E402

APPS = ("survey", "guide", "receptionist", "shopping")
VOICES = {"en": ("en-us", "en", "en-us+f3"), "de": ("de", "de+f3", "de+m3")}
OTHER_WORDS = {
    "en": ("banana", "window", "seven", "yesterday", "telephone", "coffee", "elephant",
           "tomorrow", "umbrella", "morning"),
    "de": ("Banane", "Fenster", "sieben", "gestern", "Telefon", "Elefant", "morgen",
           "Regenschirm", "Kartoffel", "Zeitung"),
}


class _Silent:
    """A source for a recognizer that only decodes whole utterances (never listens)."""
    rate = 16000

    def read(self, frames):
        return None

    def cue(self):
        pass

    def close(self):
        pass


def spoken(text: str) -> str:
    """What a person says for a button: the part before brackets, if any."""
    return re.sub(r"\s*\(.*\)\s*$", "", text) or text


def utterance(folder: Path, text: str, voice: str) -> bytes:
    path = folder / f"{abs(hash((text, voice)))}.wav"
    if not path.exists():
        subprocess.run(["espeak-ng", "-v", voice, "-w", str(path), "--", text], check=True,
                       capture_output=True)
    return WavFileSource(path)._data


def questions(app: str, language: str) -> list[tuple[str, tuple[str, ...]]]:
    """(question id, buttons) of the application, in `language`, each set of buttons once."""
    dialog = load_folder(app).dialog.in_language(language)
    found, seen = [], set()
    for question in dialog.questions:
        buttons = tuple(question["buttons"])
        if buttons and buttons not in seen:
            seen.add(buttons)
            found.append((question["id"], buttons))
    return found


def measure(app: str, language: str, recognizer: AnswerRecognizer, folder: Path,
            voices: int) -> dict:
    heard = total = rejected = others = 0
    misses: list[str] = []
    asked = questions(app, language)
    for _, buttons in asked:
        for button in buttons:
            for voice in VOICES[language][:voices]:
                got = recognizer.hear_utterance(utterance(folder, spoken(button), voice), buttons)
                total += 1
                heard += got == button
                if got != button:
                    misses.append(f"{spoken(button)!r}/{voice} -> {got!r}")
        for word in OTHER_WORDS[language]:
            got = recognizer.hear_utterance(utterance(folder, word, VOICES[language][0]), buttons)
            others += 1
            rejected += got is None
            if got is not None:
                misses.append(f"{word!r} (no answer) -> {got!r}")
    return {"heard": heard, "total": total, "rejected": rejected, "others": others,
            "misses": misses}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--apps", default=",".join(APPS))
    parser.add_argument("--languages", default="en,de")
    parser.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD)
    parser.add_argument("--voices", type=int, default=3, help="voices per language (1–3)")
    parser.add_argument("--misses", action="store_true", help="list every miss")
    args = parser.parse_args(argv)
    print(f"threshold {args.threshold:g}, {args.voices} voice(s) per language")
    print(f"{'application':14} {'lang':4} {'recognised':>16} {'rejected':>16} {'s/utt':>6}")
    with tempfile.TemporaryDirectory() as tmp:
        for language in args.languages.split(","):
            recognizer = AnswerRecognizer(_Silent(), language=language,
                                          threshold=args.threshold)
            for app in args.apps.split(","):
                start = time.perf_counter()
                result = measure(app, language, recognizer, Path(tmp), args.voices)
                count = result["total"] + result["others"]
                per = (time.perf_counter() - start) / max(1, count)
                print(f"{app:14} {language:4} "
                      f"{result['heard']:4d}/{result['total']:<4d} {100 * result['heard'] / max(1, result['total']):5.1f} % "
                      f"{result['rejected']:4d}/{result['others']:<4d} {100 * result['rejected'] / max(1, result['others']):5.1f} % "
                      f"{per:6.2f}", flush=True)
                if args.misses:
                    for miss in result["misses"]:
                        print(f"    {miss}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
