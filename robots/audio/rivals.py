"""Rival words: what the recognizer may hear instead of an answer.

A grammar that knows only the answers on the screen would force every sound onto one of them
("banana" heard as "no"). So the grammar also holds rivals: the most frequent English words of
the language model that ships with pocketsphinx (their frequency from its unigrams, their
pronunciation from its dictionary) and, for a German run, common German words pronounced by
espeak-ng. Speech that is no answer fits a rival (or a string of rivals) better and is rejected.
A rival that sounds exactly like an answer ("know" for "no", "won" for "one") is left out.
"""
from __future__ import annotations

import functools
from pathlib import Path

RIVALS = 100          # how many of the most frequent English words compete with the answers
# Common German words (function words, numbers, polite phrases, shop and office words), so that
# German speech that is no answer has German rivals too.
GERMAN_RIVALS = """
und der die das ist nicht ich sie es wir ihr er ein eine mit von zu auf für aber oder
wenn dann hier dort was wer wie wo warum heute morgen gestern gut schlecht bitte danke
hallo tschüss vielleicht sieben acht neun zehn elf zwölf hundert tausend Banane Apfel
Fenster Tür Tisch Stuhl Kaffee Wasser Auto Haus Straße Stadt Arbeit Zeit Jahr Tag Nacht
Woche Mann Frau Kind gehen kommen sehen machen sagen wissen können müssen wollen sollen
Telefon Computer Nase Hand Kopf Buch Zeitung schön schnell langsam groß klein alt neu
""".split()


@functools.lru_cache(maxsize=4)
def english_rivals(model_dir: str, count: int = RIVALS) -> tuple[tuple[str, str], ...]:
    """(word, phones) of the `count` most frequent words of the shipped English model."""
    from pocketsphinx import Config, LogMath, NGramModel

    model = Path(model_dir)
    pronunciations: dict[str, str] = {}
    with open(model / "cmudict-en-us.dict", encoding="utf-8") as dictionary:
        for line in dictionary:
            word, _, phones = line.strip().partition(" ")
            if word and "(" not in word and word.isalpha():
                pronunciations.setdefault(word, phones.strip())
    lm = NGramModel(Config(), LogMath(), str(model / "en-us.lm.bin"))
    ranked = sorted(pronunciations, key=lambda w: lm.prob([w]), reverse=True)
    return tuple((word, pronunciations[word]) for word in ranked[:count])


@functools.lru_cache(maxsize=4)
def spoken_rivals(language: str) -> tuple[tuple[str, str], ...]:
    """(word, phones) of common words of `language` as espeak-ng says them (German only)."""
    from robots.audio.pronounce import base_language, pronounce

    if base_language(language) != "de":
        return ()
    return tuple((f"de_{word.lower()}", " ".join(pronounce(word, language)))
                 for word in GERMAN_RIVALS)


def rivals_for(answer_phones: set[str], answer_words: set[str],
               rivals: tuple[tuple[str, str], ...]) -> list[tuple[str, str]]:
    """The rivals that neither are one of the answers' words nor sound exactly like an answer
    (a rival for "no" is never "know")."""
    return [(word, phones) for word, phones in rivals
            if word not in answer_words and phones not in answer_phones]
