"""Whether an utterance was the answer it resembles most: `Judgement` and the calibrated rule.

The recognizer (`recognizer.py`) measures two things about the answer that fits an utterance
best, both in the decoder's log units per frame of speech in that answer:

- **fit**: how much worse the answer explains the sound than a free loop of phones (near 0:
  as well as any sound can be explained; far below: something else was said);
- **margin**: how much better it explains the sound than the next best answer on the screen
  (0 when there is no other answer, or no other answer found a path).

A word that is no answer is forced onto the nearest answer but usually fits the others about
as badly, so its margin is small; an answer said wins over its rivals clearly, even a short one
("one", "five") whose fit is low because the free phones fit a short sound relatively well.
But a lead says *which* answer, not *whether* one was said: a word that rhymes with one answer
and not the others ("hello" against "yes" and "no") leads by as much as the answer itself. So
the margin counts only up to a **cap**: the **score** is `fit + min(margin, cap)`, and an
answer is taken when its score is at least the **threshold**. Raise the threshold to accept
fewer (fewer other words slip through, more answers are missed), lower it to accept more; a cap
of 0 leaves the fit alone. Cap and threshold per language were chosen on every set of
espeak-ng voices and words whose results are known (`benchmarks/bench_voice.py --choose`) and
checked on one held out from the choice (`--set fresh2`; docs/tablet-and-voice.md has the
figures).
"""
from __future__ import annotations

from dataclasses import dataclass

from robots.audio.pronounce import base_language

# Chosen per language on every set whose results are known (bench_voice.py --choose: the
# calibration, test, fresh and, in English, defaults sets; the pair whose worst cell - one
# set's one application, valued at the lower of its recognised and rejected rates - is
# highest, then the lower rate over all their utterances). Before, the rule was calibrated on
# espeak-ng's plain voices alone (--calibrate): -14/20 and -29/10 first, -12/20 and -27/10
# after the noise reset, -7/20 and -23/15 after the silence cut, -7/20 and -25/10 after the
# diphthong split. German is heard through the English acoustic model and fits worse
# throughout; its best rule takes the fit alone (cap 0: the rivals' decode is spared). A
# language not calibrated is heard the same way and takes German's rule.
DEFAULT_THRESHOLDS = {"en": -11.0, "de": -32.0}
MARGIN_CAPS = {"en": 25.0, "de": 0.0}
FALLBACK_LANGUAGE = "de"
THRESHOLD_RANGE = (-150.0, 150.0)


@dataclass(frozen=True)
class Judgement:
    """The answer an utterance fits best (None when no answer found a path), its fit and its
    margin over the next best answer (0 or more), per frame of speech; fit None when the free
    phones found no path (then nothing is taken)."""
    choice: str | None
    fit: float | None
    margin: float = 0.0

    def score(self, cap: float) -> float | None:
        """fit + min(margin, cap): what the threshold is compared with."""
        if self.choice is None or self.fit is None:
            return None
        return self.fit + min(self.margin, cap)

    def taken(self, threshold: float, cap: float) -> bool:
        """Whether the answer is taken: its score is at least `threshold`."""
        score = self.score(cap)
        return score is not None and score >= threshold


def check_threshold(threshold: float) -> float:
    """`threshold` as a float, or ValueError saying what it means and where it may lie."""
    low, high = THRESHOLD_RANGE
    value = float(threshold)
    if not low <= value <= high:
        raise ValueError(f"threshold must lie between {low:g} and {high:g} (the least score, "
                         f"fit + min(margin, cap) per frame, an answer is taken with; higher "
                         f"accepts fewer), not {threshold}")
    return value


def default_threshold(language: str) -> float:
    """The calibrated threshold for `language` (see DEFAULT_THRESHOLDS)."""
    return DEFAULT_THRESHOLDS.get(base_language(language), DEFAULT_THRESHOLDS[FALLBACK_LANGUAGE])


def default_margin_cap(language: str) -> float:
    """The calibrated cap of the margin for `language` (see MARGIN_CAPS)."""
    return MARGIN_CAPS.get(base_language(language), MARGIN_CAPS[FALLBACK_LANGUAGE])
