"""`AnswerRecognizer`: hears one of the answers on the screen, offline, with pocketsphinx.

Engine: pocketsphinx, because its PyPI wheel ships a US-English acoustic model, dictionary and
language model, so nothing is fetched at run time (Vosk's and Whisper's models are downloads;
Debian packages only the same US-English pocketsphinx model, and no German one).

For each question the decoder gets a grammar of the answers on the screen (each as espeak-ng
and, for English, the dictionary say it: `pronounce.py`) and of *rival* words (`rivals.py`):
the most frequent English words, and for German common German words. An utterance is taken as
the answer it matched; one that matched rivals is rejected. `threshold` is the grammar weight,
in decades, that each rival word carries against an answer's 1 (default -25: every rival word
heard costs 25 decades, so an answer wins unless rivals fit far better): **raise it to accept
fewer** — fewer wrong words slip through, more real answers are missed; lower it to accept
more. An answer is a path of its words, so the pauses people (and espeak-ng) make between
words fit it. Decoding runs in its
own thread; languages other than English are heard with the English acoustic model through
espeak-ng's pronunciation of the answers (see docs/tablet-and-voice.md for the measured rates).
"""
from __future__ import annotations

import logging
import queue
import re
import threading
from collections import deque

from robots.audio.pronounce import base_language, pronounce_words
from robots.audio.rivals import english_rivals, rivals_for, spoken_rivals
from robots.devices import AudioSource, SpeechRecognizer
from robots.exceptions import RobotError

log = logging.getLogger("interbot.listening")

DEFAULT_THRESHOLD = -25.0    # decades; see the module's doc and docs/tablet-and-voice.md
CHUNK = 1024                  # samples per decoder call (64 ms at 16 kHz)
NUMBERS = ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten")


def spoken_forms(choice: str) -> str:
    """How an answer is written for the English dictionary: lower case words, digits as
    English numbers ('3' -> 'three')."""
    words = []
    for word in re.findall(r"[\w']+", choice.lower()):
        if word.isdigit() and int(word) < len(NUMBERS):
            word = NUMBERS[int(word)]
        words.append(word)
    return " ".join(words)


def sayings(choice: str) -> list[str]:
    """The ways a button may be said: its whole text and, for "Room S1 (seminar room)", also
    the part before the brackets and the part inside them."""
    forms = [choice]
    match = re.fullmatch(r"\s*(.*?)\s*\((.*)\)\s*", choice)
    if match:
        forms += [part for part in match.groups() if part.strip()]
    return list(dict.fromkeys(f for f in forms if re.search(r"\w", f)))


def check_language(language: str) -> None:
    """Refuse, with the reason, a language espeak-ng cannot pronounce answers in."""
    from robots.audio.espeak import espeak_voices
    try:
        voices = espeak_voices(language)
    except OSError as exc:
        raise RobotError(f"spoken answers need espeak-ng to pronounce them: {exc}") from exc
    if not voices:
        raise RobotError(f"spoken answers in '{language}' cannot be recognised: espeak-ng, "
                         f"which pronounces the answers, has no voice for it")


class AnswerRecognizer(SpeechRecognizer):
    def __init__(self, source: AudioSource, language: str = "en",
                 threshold: float = DEFAULT_THRESHOLD) -> None:
        check_language(language)
        try:
            from pocketsphinx import Decoder
        except ImportError as exc:
            raise RobotError("speech recognition needs pocketsphinx (pip install "
                             "pocketsphinx)") from exc
        from pocketsphinx import get_model_path
        self.source = source
        self.language = language
        self.threshold = float(threshold)
        if not -150 <= self.threshold <= 150:
            raise RobotError(f"threshold must lie between -150 and 150 (decades of grammar "
                             f"weight; higher accepts fewer), not {threshold}")
        self.decoder = Decoder(lm=None, loglevel="FATAL", samprate=source.rate)
        own = spoken_rivals(language)
        self.rivals = english_rivals(str(get_model_path() + "/en-us")) + own
        for word, phones in own:
            self.decoder.add_word(word, phones, False)
        self._words = 0
        self._lock = threading.Lock()
        self._wanted: tuple[str, tuple[str, ...]] | None = None
        self._generation = 0
        self._heard: queue.Queue[tuple[str, str]] = queue.Queue()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.rejected: deque[str] = deque(maxlen=50)   # heard, but not an answer (diagnosis)

    def listen(self, prompt_id: str, choices: tuple[str, ...]) -> None:
        with self._lock:
            self._wanted = (str(prompt_id), tuple(str(c) for c in choices))
            self._generation += 1
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="recognizer", daemon=True)
            self._thread.start()

    def stop(self) -> None:
        with self._lock:
            self._wanted = None
            self._generation += 1

    def take_heard(self) -> tuple[str, str] | None:
        try:
            return self._heard.get_nowait()
        except queue.Empty:
            return None

    def hear_utterance(self, audio: bytes, choices: tuple[str, ...]) -> str | None:
        """The choice one whole utterance (16 kHz samples, silence either side) says, or None;
        decoded at once, with the grammar and rivals the listening thread uses (benchmarks)."""
        wanted = self._sayable(("utterance", tuple(choices)))
        if wanted is None:
            return None
        self.decoder.add_fsg("answers", self._grammar(wanted[1]))
        self.decoder.activate_search("answers")
        self.decoder.start_utt()
        self.decoder.process_raw(audio, False, True)
        self.decoder.end_utt()
        self._judge(wanted)
        heard = self.take_heard()
        return heard[1] if heard is not None else None

    def wait(self, timeout: float) -> None:
        """Wait until the source has ended and everything heard is decoded (tests, files)."""
        if self._thread is not None:
            self._thread.join(timeout)

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(2.0)
        self.source.close()

    # --- the decoder thread ---------------------------------------------------------------
    def _run(self) -> None:
        """Cut the sound into utterances (pocketsphinx's endpointer) and judge each one against
        the answers wanted when it began; a change of question drops the utterance under way."""
        from pocketsphinx import Endpointer
        endpointer = Endpointer(sample_rate=self.source.rate)
        size = endpointer.frame_bytes
        decoder, generation, wanted = self.decoder, -1, None
        buffer, decoding = b"", False
        while not self._stop.is_set():
            with self._lock:
                if generation != self._generation:
                    generation, wanted = self._generation, self._sayable(self._wanted)
                    if decoding:
                        decoder.end_utt()
                        decoding = False
                    if wanted is not None:
                        decoder.add_fsg("answers", self._grammar(wanted[1]))
                        decoder.activate_search("answers")
                        self.source.cue()
            chunk = self.source.read(CHUNK)
            if chunk is None:
                break
            buffer += chunk
            while len(buffer) >= size:
                frame, buffer = buffer[:size], buffer[size:]
                was_speaking = endpointer.in_speech
                speech = endpointer.process(frame)
                if speech is None or wanted is None:
                    continue
                if not was_speaking:
                    decoder.start_utt()
                    decoding = True
                if decoding:
                    decoder.process_raw(speech, False, False)
                    if not endpointer.in_speech:
                        decoder.end_utt()
                        decoding = False
                        self._judge(wanted)
        if decoding:
            rest = endpointer.end_stream(buffer[:size]) if endpointer.in_speech else None
            if rest:
                decoder.process_raw(rest, False, False)
            decoder.end_utt()
            self._judge(wanted)

    def _sayable(self, wanted) -> tuple[str, dict[str, str]] | None:
        """(prompt_id, {grammar path: choice}) for the choices that can be pronounced, or None.
        Each way of saying a choice (`sayings`) is a path of words, with espeak-ng's
        pronunciation in the run's language and, in English, the dictionary's too; a path is
        written as its words joined by spaces, as the decoder's hypothesis reads."""
        if wanted is None:
            return None
        prompt_id, choices = wanted
        paths = {}
        for choice in choices:
            for pronunciation in self._pronunciations(choice):
                self._words += 1
                names = []
                for index, phones in enumerate(pronunciation):
                    name = f"answer_{self._words}_{index}"
                    self.decoder.add_word(name, phones, False)
                    names.append(name)
                paths[" ".join(names)] = choice
        return (prompt_id, paths) if paths else None

    def _pronunciations(self, choice: str) -> list[tuple[str, ...]]:
        """Each way of saying `choice`, as the phones of each of its words."""
        found: list[tuple[str, ...]] = []
        for saying in sayings(choice):
            try:
                found.append(tuple(" ".join(p) for p in pronounce_words(saying, self.language)))
            except (ValueError, RobotError) as exc:
                log.info("listening: '%s' cannot be pronounced: %s", saying, exc)
            if base_language(self.language) == "en":
                form = spoken_forms(saying).split()
                looked_up = [self.decoder.lookup_word(w) for w in form]
                if form and all(looked_up):
                    found.append(tuple(looked_up))
        return [p for p in dict.fromkeys(found) if p]

    def _sounds(self, path: str) -> str:
        """A path's phones, word by word: the decoder may name a path by the words of another
        with the same sound (its lexicon tree shares them), so paths are compared by sound."""
        return "|".join(self.decoder.lookup_word(w) or w for w in path.split())

    def _grammar(self, paths: dict[str, str]):
        """A finite-state grammar: one answer (a path of its words), or a string of rivals,
        each rival word weighing 10**threshold (a hub state keeps the rival loop linear in the
        number of rivals: a JSGF loop was quadratic, 32 s per utterance for 150 rivals)."""
        sounds = {" ".join(self.decoder.lookup_word(w) for w in path.split()) for path in paths}
        spelled = {w for choice in paths.values() for w in spoken_forms(choice).split()}
        rivals = [word for word, _ in rivals_for(sounds, spelled, self.rivals)]
        answer = 1.0 / len(paths)
        rival = 10.0 ** self.threshold
        start, final, said, hub = 0, 1, 2, 3
        transitions, state = [], hub
        for path in sorted(paths):
            words = path.split()
            here, weight = start, answer
            for index, word in enumerate(words):
                if index == len(words) - 1:
                    after = final
                else:
                    state += 1
                    after = state
                transitions.append((here, after, weight, word))
                here, weight = after, 1.0
        if rivals:
            transitions += [(start, said, rival, word) for word in rivals]
            transitions += [(said, final, 0.5), (said, hub, 0.5)]
            transitions += [(hub, said, rival, word) for word in rivals]
        return self.decoder.create_fsg("answers", start, final, transitions)

    def _judge(self, wanted: tuple[str, dict[str, str]]) -> None:
        hypothesis = self.decoder.hyp()
        said = hypothesis.hypstr.strip() if hypothesis is not None else ""
        prompt_id, words = wanted
        sounds = {self._sounds(path): choice for path, choice in words.items()}
        if said and said not in words and self._sounds(said) in sounds:
            said = next(p for p, c in words.items() if self._sounds(p) == self._sounds(said))
        if said in words:
            log.info("heard '%s' for %s", words[said], prompt_id)
            self._heard.put((prompt_id, words[said]))
        else:
            self.rejected.append(said)
