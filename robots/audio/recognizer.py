"""`AnswerRecognizer`: hears one of the answers on the screen, offline, with pocketsphinx.

Engine: pocketsphinx, because its PyPI wheel ships a US-English acoustic model, dictionary and
language model, so nothing is fetched at run time (Vosk's and Whisper's models are downloads;
Debian packages only the same US-English pocketsphinx model, and neither PyPI nor Debian has a
German one).

Each utterance is cut to its speech with 0.1 s either side (the features' mean normalisation
is a mean over the whole utterance, so a short answer must not be normalised mostly on
silence), then decoded three times (utterance verification): with a grammar that holds only
the answers on the screen, each a path of its words (each word as espeak-ng and, for English,
the dictionary say it: `pronounce.py`), which says *which* answer it most resembles; with a
free loop of the model's phones, which fits any sound as well as the model can; and with the
other answers only, the best answer's rivals (spared when the margin's cap is 0). Each
decode starts pocketsphinx's noise estimate afresh, so an utterance is judged the same
whatever was heard before it. How much worse per frame of speech the best
answer fits than the free phones (its fit) and how much better than its best rival (its
margin) say *whether* it was that answer at all (`confidence.py`): `threshold` is the least
score (the fit plus the margin up to `margin_cap`) taken. **Raise it to accept fewer** — fewer
other words slip through, more real answers are missed; lower it to accept more. The defaults
were chosen on every set of espeak-ng voices and words whose results are known, and checked on
a set held out from the choice (benchmarks/bench_voice.py --choose, --set fresh2). Languages
other than English are heard with the English acoustic model through espeak-ng's
pronunciation of the answers (see docs/tablet-and-voice.md for the measured rates).
"""
from __future__ import annotations

import logging
import queue
import re
import threading
import warnings
from collections import deque

import numpy as np

from robots.audio.confidence import (DEFAULT_THRESHOLDS, Judgement, check_threshold,
                                     default_margin_cap, default_threshold)
from robots.audio.pronounce import base_language, pronounce_words, split_diphthongs
from robots.devices import AudioSource, SpeechRecognizer
from robots.exceptions import RobotError

log = logging.getLogger("interbot.listening")

DEFAULT_THRESHOLD = DEFAULT_THRESHOLDS["en"]      # the rules per language: confidence.py
CHUNK = 1024                  # samples per decoder call (64 ms at 16 kHz)
# The acoustic model's phones: the free loop that any sound fits (its words are phone_aa, …).
PHONES = ("AA AE AH AO AW AY B CH D DH EH ER EY F G HH IH IY JH K L M N NG OW OY P R S SH T "
          "TH UH UW V W Y Z ZH").split()
PHONE_STEP = 0.1              # grammar weight of each further phone of the loop
FILLERS = {"<s>", "</s>", "<sil>", "(NULL)", "[NOISE]"}
# The search must keep every path: espeak-ng's voices (German above all) fit the English model
# so loosely that the default beams drop the right answer's path and nothing is heard. The
# lattice's best path (bestpath) loses the later words of a several-word answer: off. Every
# senone is scored in every frame (compallsen), so that both searches' scores are on the same
# footing and can be compared.
DECODER_OPTIONS = dict(bestpath=False, compallsen=True, beam=1e-150, wbeam=1e-120,
                       pbeam=1e-150)
# The noise floor (RMS, in 16-bit sample units: about 43 dB under espeak-ng's speech, whose RMS
# is near 2 800) laid under every utterance before decoding, seeded so the same sound always
# decodes the same; 0 for none. Digital silence (the exact zeros of a synthesised or padded
# file) made the feature normalisation take speech for silence; with this floor the
# calibration set's lower rate rose from 90.0 to 91.9 % in English and from 77.2 to 87.0 % in
# German. Louder floors (100, 300) did better on the calibration set but, at 300, worse on the
# held-out voices; 100 did better on every known set too, but let "banana" through as "no"
# in the listening path (docs/tablet-and-voice.md), so the floor stays.
NOISE_FLOOR = 20.0
# Seconds of sound kept either side of the speech an utterance holds (None: all of it). The
# features' mean normalisation (`cmn batch`) is a mean over the whole utterance, silence
# included: a short answer in a long silence was normalised mostly on the silence. Chosen on
# the calibration set among 0, 0.1, 0.2 and 0.3 s (the highest sum over English and German of
# the lower of the two rates, each at its calibrated rule: docs/tablet-and-voice.md).
SPEECH_PAD: float | None = 0.1
# Each diphthong that glides up to "ee" (AY, EY, OY) may also be said as its two ends (AA IY, …:
# `pronounce.split_diphthongs`): espeak-ng draws "five" out over a long glide that the model's
# one diphthong fits badly ("5" by the calibration voices fitted −19 to −31 per frame; with the
# two ends −10 to −24). Chosen on the calibration set only (docs/tablet-and-voice.md: the
# rising-to-"oo" ones, OW and AW, split too, made "banana" fit "no" far better).
SPLIT_DIPHTHONGS = True
VAD_FRAME = 0.03              # s: the voice activity detector's frame (webrtc's: 10, 20, 30 ms)
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


def with_noise_floor(audio: bytes, rms: float) -> bytes:
    """`audio` with seeded white noise of `rms` added: digital silence (exact zeros, as in a
    synthesised or padded file) has no noise floor, which every microphone has."""
    if rms <= 0:
        return audio
    samples = np.frombuffer(audio, dtype="<i2").astype(float)
    samples += np.random.default_rng(0).normal(0.0, rms, samples.size)
    return np.clip(np.rint(samples), -32768, 32767).astype("<i2").tobytes()


def trimmed(audio: bytes, pad: float | None, rate: int = 16000) -> bytes:
    """`audio` cut to the speech in it, with `pad` seconds either side (as far as the sound
    goes): the frames from the first to the last that pocketsphinx's voice activity detector
    (webrtc's) takes for speech. Unchanged when `pad` is None or no frame is speech."""
    if pad is None:
        return audio
    from pocketsphinx import Vad
    vad = Vad(sample_rate=rate, frame_length=VAD_FRAME)
    size = vad.frame_bytes
    speech = [start for start in range(0, len(audio) - size + 1, size)
              if vad.is_speech(audio[start:start + size])]
    if not speech:
        return audio
    margin = 2 * int(round(pad * rate))
    return audio[max(0, speech[0] - margin):speech[-1] + size + margin]


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
                 threshold: float | None = None, noise_floor: float = NOISE_FLOOR,
                 margin_cap: float | None = None,
                 speech_pad: float | None = SPEECH_PAD,
                 split_diphthongs: bool = SPLIT_DIPHTHONGS) -> None:
        check_language(language)
        try:
            from pocketsphinx import Decoder
        except ImportError as exc:
            raise RobotError("speech recognition needs pocketsphinx (pip install "
                             "pocketsphinx)") from exc
        self.source = source
        self.language = language
        if threshold is None:
            threshold = default_threshold(language)
        try:
            self.threshold = check_threshold(threshold)
        except ValueError as exc:
            raise RobotError(str(exc)) from exc
        self.margin_cap = float(default_margin_cap(language) if margin_cap is None
                                else margin_cap)
        if not self.margin_cap >= 0:
            raise RobotError(f"margin_cap must be 0 or more (the most that the lead over the "
                             f"next best answer adds to the score), not {margin_cap}")
        self.noise_floor = float(noise_floor)
        if speech_pad is not None and not speech_pad >= 0:
            raise RobotError(f"speech_pad must be 0 or more (seconds of sound kept either side "
                             f"of the speech), not {speech_pad}")
        self.speech_pad = speech_pad
        self.split_diphthongs = bool(split_diphthongs)
        self.decoder = Decoder(lm=None, loglevel="FATAL", samprate=source.rate,
                               **DECODER_OPTIONS)
        self._add_phone_loop()
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
        decided as the listening thread decides (benchmarks)."""
        wanted = self._sayable(("utterance", tuple(choices)))
        if wanted is None:
            return None
        self.decoder.add_fsg("answers", self._grammar(wanted[1]))
        self._judge(audio, wanted)
        heard = self.take_heard()
        return heard[1] if heard is not None else None

    def judge(self, audio: bytes, choices: tuple[str, ...]) -> Judgement:
        """The choice that fits one whole utterance best, with its fit and margin, the
        threshold aside: what calibration needs."""
        wanted = self._sayable(("utterance", tuple(choices)))
        if wanted is None:
            return Judgement(None, None)
        self.decoder.add_fsg("answers", self._grammar(wanted[1]))
        return self._judgement(audio, wanted[1])

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
        generation, wanted = -1, None
        buffer, speech = b"", None
        while not self._stop.is_set():
            with self._lock:
                if generation != self._generation:
                    generation, wanted = self._generation, self._sayable(self._wanted)
                    speech = None
                    if wanted is not None:
                        self.decoder.add_fsg("answers", self._grammar(wanted[1]))
                        self.source.cue()
            chunk = self.source.read(CHUNK)
            if chunk is None:
                break
            buffer += chunk
            while len(buffer) >= size:
                frame, buffer = buffer[:size], buffer[size:]
                heard = endpointer.process(frame)
                if heard is None or wanted is None:
                    continue
                speech = (speech or b"") + heard
                if not endpointer.in_speech:
                    self._judge(speech, wanted)
                    speech = None
        if speech is not None and wanted is not None:
            rest = endpointer.end_stream(buffer[:size]) if endpointer.in_speech else None
            self._judge(speech + (rest or b""), wanted)

    def _add_phone_loop(self) -> None:
        """The free loop of phones (one or more), the yardstick an answer's fit is taken on."""
        for phone in PHONES:
            self.decoder.add_word(f"phone_{phone.lower()}", phone, False)
        words = [f"phone_{phone.lower()}" for phone in PHONES]
        transitions = [(0, 1, 1.0, word) for word in words]
        transitions += [(1, 1, PHONE_STEP, word) for word in words]
        self.decoder.add_fsg("phones", self.decoder.create_fsg("phones", 0, 1, transitions))

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
        if self.split_diphthongs:
            found += [tuple(" ".join(split_diphthongs(w.split())) for w in words)
                      for words in found]
        return [p for p in dict.fromkeys(found) if p]

    def _sounds(self, path: str) -> str:
        """A path's phones, word by word: the decoder may name a path by the words of another
        with the same sound (its lexicon tree shares them), so paths are compared by sound."""
        return "|".join(self.decoder.lookup_word(w) or w for w in path.split())

    def _grammar(self, paths: dict[str, str], name: str = "answers"):
        """A finite-state grammar of the answers only: each way of saying one is a path of its
        words (a pause may fall between them); all ways are equally likely."""
        start, final, state = 0, 1, 1
        weight, transitions = 1.0 / len(paths), []
        for path in sorted(paths):
            words, here = path.split(), start
            for index, word in enumerate(words):
                if index == len(words) - 1:
                    after = final
                else:
                    state += 1
                    after = state
                transitions.append((here, after, weight if here == start else 1.0, word))
                here = after
        return self.decoder.create_fsg(name, start, final, transitions)

    def _decode(self, search: str, audio: bytes) -> tuple[str, int, int] | None:
        """(hypothesis, its score in the decoder's log units, frames of speech in it) of one
        whole utterance under `search`, or None when the search found no path."""
        decoder = self.decoder
        decoder.activate_search(search)
        self._forget_noise()
        decoder.start_utt()
        decoder.process_raw(audio, False, True)
        decoder.end_utt()
        hypothesis = decoder.hyp()
        if hypothesis is None or not hypothesis.hypstr.strip() or hypothesis.score <= 0.0:
            return None
        frames = sum(s.end_frame - s.start_frame + 1 for s in decoder.seg()
                     if s.word not in FILLERS)
        return (hypothesis.hypstr.strip(), decoder.get_logmath().log(hypothesis.score),
                max(1, frames))

    def _forget_noise(self) -> None:
        """Start the noise estimate afresh, from the sound about to be decoded. The acoustic
        model's `feat.params` turns on noise removal, whose estimate pocketsphinx otherwise
        carries from one decode to the next (its batch mean normalisation is per utterance
        already): the same "yes" then fitted 5.8 per frame as the first utterance and 0.1
        after it, and the three decodes of one utterance each started from another estimate.
        Reset, every decode of the same sound scores the same, whatever was heard before.
        (pocketsphinx calls this reset, `start_stream`, deprecated and unnecessary; for this
        use it is neither: tests/robots/test_audio.py checks that it still has its effect.)"""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            self.decoder.start_stream()

    def _judgement(self, audio: bytes, paths: dict[str, str],
                   margin: bool = True) -> Judgement:
        """The answer an utterance resembles most; how much worse per frame of speech it fits
        than the free phones (0: as well; the more negative, the less it is that); and how much
        better than the best of the other answers (0 when there is none, or when `margin` is
        false: a cap of 0 makes it count nothing, so the rivals' decode is spared)."""
        audio = with_noise_floor(trimmed(audio, self.speech_pad, self.source.rate),
                                 self.noise_floor)
        said = self._decode("answers", audio)
        if said is None:
            return Judgement(None, None)
        choice = self._choice(said[0], paths)
        free = self._decode("phones", audio)
        if free is None:
            return Judgement(choice, None)
        fit = (said[1] - free[1]) / said[2]
        rivals = {p: c for p, c in paths.items() if c != choice}
        if not rivals or not margin:
            return Judgement(choice, fit)
        self.decoder.add_fsg("rivals", self._grammar(rivals, "rivals"))
        rival = self._decode("rivals", audio)
        margin = 0.0 if rival is None else max(0.0, (said[1] - rival[1]) / said[2])
        return Judgement(choice, fit, margin)

    def _choice(self, hypothesis: str, paths: dict[str, str]) -> str | None:
        """The choice a grammar path names (or another path of the same sound)."""
        path = " ".join(word for word in hypothesis.split() if word not in FILLERS)
        choice = paths.get(path)
        if choice is None:            # named by another word of the same sound
            sound = self._sounds(path)
            choice = next((c for p, c in paths.items() if self._sounds(p) == sound), None)
        return choice

    def _judge(self, audio: bytes, wanted: tuple[str, dict[str, str]]) -> None:
        prompt_id, paths = wanted
        judgement = self._judgement(audio, paths, margin=self.margin_cap > 0)
        score = judgement.score(self.margin_cap)
        if judgement.taken(self.threshold, self.margin_cap):
            log.info("heard '%s' for %s (score %.1f: fit %.1f, margin %.1f)", judgement.choice,
                     prompt_id, score, judgement.fit, judgement.margin)
            self._heard.put((prompt_id, judgement.choice))
        else:
            self.rejected.append(f"{judgement.choice} (score "
                                 f"{score if score is None else round(score, 1)})")
