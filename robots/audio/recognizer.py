"""`AnswerRecognizer`: hears one of the answers on the screen, offline, with pocketsphinx.

The decoder only knows the current answers (a JSGF grammar built from the buttons) plus a
*filler*: any sequence of English phones. Speech that is not one of the answers fits the filler
better and is rejected; `threshold` is the filler's price per phone (the word insertion penalty):
lower accepts fewer answers and rejects more wrong words. Only the English model ships inside the
pocketsphinx wheel, so only English answers can be recognised. Decoding runs in its own thread.
"""
from __future__ import annotations

import logging
import queue
import re
import threading
from collections import deque

from robots.devices import AudioSource, SpeechRecognizer
from robots.exceptions import RobotError

log = logging.getLogger("interbot.listening")

DEFAULT_THRESHOLD = 1e-2
CHUNK = 1024                  # samples per decoder call (64 ms at 16 kHz)
PHONES = ("AA AE AH AO AW AY B CH D DH EH ER EY F G HH IH IY JH K L M N NG OW OY P R S SH T TH "
          "UH UW V W Y Z ZH").split()
NUMBERS = ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten")


def spoken_forms(choice: str) -> str:
    """How an answer is said: lower case words, digits as English numbers ('3' -> 'three')."""
    words = []
    for word in re.findall(r"[\w']+", choice.lower()):
        if word.isdigit() and int(word) < len(NUMBERS):
            word = NUMBERS[int(word)]
        words.append(word)
    return " ".join(words)


def check_language(language: str) -> None:
    """Refuse, with the reason, a language the shipped model cannot recognise."""
    if not language.lower().startswith("en"):
        raise RobotError(f"speech recognition has an English model only (pocketsphinx's "
                         f"wheel); language '{language}' cannot be recognised")


class AnswerRecognizer(SpeechRecognizer):
    def __init__(self, source: AudioSource, language: str = "en",
                 threshold: float = DEFAULT_THRESHOLD) -> None:
        check_language(language)
        try:
            from pocketsphinx import Decoder
        except ImportError as exc:
            raise RobotError("speech recognition needs pocketsphinx (pip install "
                             "pocketsphinx)") from exc
        self.source = source
        self.decoder = Decoder(lm=None, loglevel="FATAL", samprate=source.rate, wip=threshold)
        for phone in PHONES:
            self.decoder.add_word(f"filler_{phone.lower()}", phone, False)
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
                        decoder.add_jsgf_string("answers", _grammar(wanted[1]))
                        decoder.activate_search("answers")
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
        """(prompt_id, {spoken form: choice}) for the choices in the dictionary, or None."""
        if wanted is None:
            return None
        prompt_id, choices = wanted
        forms = {}
        for choice in choices:
            form = spoken_forms(choice)
            if form and all(self.decoder.lookup_word(w) for w in form.split()):
                forms[form] = choice
            else:
                log.info("listening: '%s' cannot be said (not in the English dictionary)", choice)
        return (prompt_id, forms) if forms else None

    def _judge(self, wanted: tuple[str, dict[str, str]]) -> None:
        hypothesis = self.decoder.hyp()
        said = hypothesis.hypstr.strip() if hypothesis is not None else ""
        prompt_id, forms = wanted
        if said in forms:
            log.info("heard '%s' for %s", forms[said], prompt_id)
            self._heard.put((prompt_id, forms[said]))
        else:
            self.rejected.append(said)


def _grammar(forms: dict[str, str]) -> str:
    answers = " | ".join(sorted(forms))
    filler = " | ".join(f"filler_{phone.lower()}" for phone in PHONES)
    return ("#JSGF V1.0;\ngrammar answers;\n"
            f"public <utterance> = {answers} | <filler> ;\n"
            f"<filler> = ( {filler} )+ ;\n")
