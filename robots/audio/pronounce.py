"""How an answer is said: espeak-ng's phonemes for the text, in the recognizer's phone set.

The recognizer (pocketsphinx, `recognizer.py`) has an acoustic model of US-English phones
(ARPAbet: AA, AE, … ZH). espeak-ng knows how a text is spoken in many languages — numbers,
abbreviations (`Dr.`), names and all — and writes it in IPA (`espeak-ng -q --ipa=3`). Mapping
those IPA symbols onto the nearest English phones gives a pronunciation for any button text in
any language espeak-ng speaks: German answers are then heard with the English acoustic model
(no German model is packaged for pocketsphinx; see docs/tablet-and-voice.md).

`ipa_to_phones` is pure (text in, phones out); `espeak_ipa` runs espeak-ng.
"""
from __future__ import annotations

import functools
import shutil
import subprocess

from robots.exceptions import RobotError

TIE = "\u200d"                # espeak-ng's --ipa=3 joins the parts of a diphthong with a ZWJ
IGNORED = set("ˈˌ.ʔ̩̃‿-") | {"\u0329", "\u0303", "\u032f", "ˑ"}   # stress, syllable, glottal stop…

# Longest symbols first; the values are ARPAbet phones of the English acoustic model.
IPA_PHONES: dict[str, tuple[str, ...]] = {
    # diphthongs (tied or not)
    "a\u200dɪ": ("AY",), "aɪ": ("AY",), "a\u200dʊ": ("AW",), "aʊ": ("AW",),
    "e\u200dɪ": ("EY",), "eɪ": ("EY",), "o\u200dʊ": ("OW",), "oʊ": ("OW",),
    "ə\u200dʊ": ("OW",), "əʊ": ("OW",), "ɔ\u200dɪ": ("OY",), "ɔɪ": ("OY",),
    "ɔ\u200dʏ": ("OY",), "ɔʏ": ("OY",), "ɪ\u200də": ("IH", "R"), "e\u200də": ("EH", "R"),
    "ʊ\u200də": ("UH", "R"), "a\u200dɪ\u200dɚ": ("AY", "ER"),
    # affricates
    "t\u200dʃ": ("CH",), "tʃ": ("CH",), "d\u200dʒ": ("JH",), "dʒ": ("JH",),
    "t\u200ds": ("T", "S"), "p\u200df": ("P", "F"),
    # vowels
    "ɑː": ("AA",), "ɑ": ("AA",), "aː": ("AA",), "a": ("AA",), "æ": ("AE",), "ɐ": ("AH",),
    "ʌ": ("AH",), "ə": ("AH",), "ɔː": ("AO",), "ɔ": ("AO",), "ɒ": ("AA",), "ɛː": ("EH",),
    "ɛ": ("EH",), "eː": ("EY",), "e": ("EH",), "ɚ": ("ER",), "ɜː": ("ER",), "ɜ": ("ER",),
    "ɝ": ("ER",), "ɪ": ("IH",), "ᵻ": ("IH",), "ɨ": ("IH",), "iː": ("IY",), "i": ("IY",),
    "oː": ("OW",), "o": ("OW",), "ʊ": ("UH",), "uː": ("UW",), "u": ("UW",),
    "yː": ("UW",), "y": ("UW",), "ʏ": ("UH",), "øː": ("ER",), "ø": ("ER",), "œ": ("ER",),
    # consonants
    "b": ("B",), "d": ("D",), "ð": ("DH",), "f": ("F",), "ɡ": ("G",), "g": ("G",),
    "h": ("HH",), "k": ("K",), "l": ("L",), "ɫ": ("L",), "m": ("M",), "n": ("N",),
    "ŋ": ("NG",), "p": ("P",), "ɹ": ("R",), "r": ("R",), "ʁ": ("R",), "s": ("S",),
    "ʃ": ("SH",), "t": ("T",), "θ": ("TH",), "v": ("V",), "w": ("W",), "j": ("Y",),
    "z": ("Z",), "ʒ": ("ZH",), "ç": ("HH",), "x": ("HH",), "χ": ("HH",), "ʋ": ("V",),
    "ɬ": ("L",), "ɲ": ("N", "Y"),
}
# The flap: a t or d in US English ("water"), an r in German ("Brot").
FLAP = {"en": ("D",), "de": ("R",)}
_LONGEST = max(len(symbol) for symbol in IPA_PHONES)


def ipa_to_phones(ipa: str, language: str = "en") -> list[str]:
    """ARPAbet phones for an IPA string; an unknown symbol raises ValueError naming it."""
    phones: list[str] = []
    text = ipa.replace("ː\u200d", "ː").strip()
    index = 0
    while index < len(text):
        char = text[index]
        if char.isspace() or char in IGNORED or char == TIE:
            index += 1
            continue
        if char == "ɾ":
            phones += FLAP.get(base_language(language), ("R",))
            index += 1
            continue
        for size in range(min(_LONGEST, len(text) - index), 0, -1):
            piece = text[index:index + size]
            if piece in IPA_PHONES:
                phones += IPA_PHONES[piece]
                index += size
                break
        else:
            if char == "ː":          # a length mark after a symbol mapped on its own
                index += 1
                continue
            raise ValueError(f"no English phone for the IPA symbol {char!r} (U+{ord(char):04X}) "
                             f"in {ipa!r}")
    return phones


def base_language(language: str) -> str:
    """'en-us' -> 'en', 'de-AT' -> 'de'."""
    return language.lower().replace("_", "-").split("-")[0]


@functools.lru_cache(maxsize=512)
def espeak_ipa(text: str, voice: str) -> str:
    """How espeak-ng's `voice` says `text`, in IPA (words separated by spaces)."""
    executable = shutil.which("espeak-ng")
    if executable is None:
        raise RobotError("pronouncing answers needs espeak-ng (apt-get install espeak-ng)")
    result = subprocess.run([executable, "-q", "--ipa=3", "-v", voice, "--", text],
                            capture_output=True, text=True, timeout=10, check=False)
    if result.returncode != 0:
        raise RobotError(f"espeak-ng cannot pronounce {text!r} with voice {voice}: "
                         f"{result.stderr.strip()[:200]}")
    return " ".join(result.stdout.split())


def pronounce(text: str, language: str) -> list[str]:
    """ARPAbet phones for `text` as espeak-ng says it in `language` (en, de, en-us…)."""
    return ipa_to_phones(espeak_ipa(text, language), language)


def pronounce_words(text: str, language: str) -> list[list[str]]:
    """ARPAbet phones per spoken word of `text` (espeak-ng separates words by spaces), so the
    recognizer lets a pause fall between words."""
    words = [ipa_to_phones(word, language) for word in espeak_ipa(text, language).split()]
    return [phones for phones in words if phones]


# The diphthongs that glide up to "ee", said as their two ends: espeak-ng draws them out over a
# long glide (the "i" of "five" lasts a quarter of a second and ends high), which the acoustic
# model's one three-state diphthong fits badly; its two ends, as two phones, fit the glide.
# (OW and AW, which glide to "oo", are not split: their ends, AH UW and AA UW, fitted words
# that are no answer - "banana" to "no" - as well as the answers: docs/tablet-and-voice.md.)
DIPHTHONG_ENDS = {"AY": ("AA", "IY"), "EY": ("EH", "IY"), "OY": ("AO", "IY")}


def split_diphthongs(phones: list[str]) -> list[str]:
    """`phones` with each diphthong replaced by its two ends (AY -> AA IY)."""
    return [part for phone in phones for part in DIPHTHONG_ENDS.get(phone, (phone,))]
