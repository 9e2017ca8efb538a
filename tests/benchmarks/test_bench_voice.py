"""The spoken-answer benchmark's bookkeeping (benchmarks/bench_voice.py), without sound: how it
counts recognised and rejected utterances under a rule, and which rule its calibration picks.
The recognizer itself is tested in tests/robots/test_audio.py."""
from __future__ import annotations

import pytest

from robots.audio.confidence import Judgement
from tests.benchmarks import benchmark_script


@pytest.fixture(scope="module")
def bench():
    with benchmark_script("bench_voice.py", "bench_voice") as module:
        yield module


def answer(app, right, fit, margin):
    return {"app": app, "right": right, "judgement": Judgement("x", fit, margin)}


def other(app, fit, margin):
    return {"app": app, "judgement": Judgement("x", fit, margin)}


def test_an_answer_counts_only_when_right_and_taken(bench):
    answers = [answer("a", True, -10, 30), answer("a", False, 0, 30), answer("a", True, -50, 0)]
    assert bench.recognised(answers, (-20.0, 20.0)) == (1, 3)
    assert bench.recognised(answers, (-60.0, 0.0)) == (2, 3)
    assert bench.rejected([other("a", -30, 5), other("a", -5, 0)], (-20.0, 20.0)) == (1, 2)


def test_calibration_caps_the_margin_when_a_rhyming_word_leads(bench, capsys):
    """A short answer fits lower than a word that is none but leads its rival; a word that
    rhymes with one answer leads by even more: the fit alone (cap 0) takes the word that fits
    well, the whole margin (no cap) the rhyme, and only a capped margin takes every answer
    and rejects every other word."""
    answers = [answer("a", True, -30, 40), answer("a", True, -5, 40), answer("b", True, -8, 60)]
    others = [other("a", -40, 60), other("b", -25, 2), other("b", -60, 3)]
    for uncalibrated in ((-30.0, 0.0), (10.0, 1000.0)):
        assert bench.lower_rate(answers, others, uncalibrated) < 1.0
    rule = bench.calibrate(answers, others)
    threshold, cap = rule
    assert bench.recognised(answers, rule) == (3, 3) and bench.rejected(others, rule) == (3, 3)
    assert 0 < cap < 1000 and -30 + min(40, cap) >= threshold > -40 + min(60, cap)
    assert "calibrated: threshold" in capsys.readouterr().out


def test_the_choice_on_the_known_sets_raises_the_worst_cell(bench, capsys):
    """--choose values each set's each application at the lower of its two rates and takes
    the rule whose lowest such cell is highest: here the one answer of set "b" that fits
    worst must be heard and the one other word of set "a" refused; ties go to the smaller
    cap and the higher threshold."""
    answers = [dict(answer("x", True, -5, 0), set="a") for _ in range(9)]
    answers.append(dict(answer("x", True, -20, 0), set="b"))
    others = [dict(other("x", -22, 0), set="a"), dict(other("x", -40, 0), set="b")]
    assert bench.worst_cell(answers, others, (-10.0, 0.0)) == 0.0      # b's answer missed
    assert bench.worst_cell(answers, others, (-30.0, 0.0)) == 0.0      # a's word taken
    rule = bench.choose(answers, others)
    assert rule == (-20.0, 0.0) and bench.worst_cell(answers, others, rule) == 1.0
    assert "chosen: threshold -20, margin cap 0" in capsys.readouterr().out


def test_the_fresh_set_shares_no_voice_or_word_with_the_sets_rules_are_chosen_or_shown_on(bench):
    """The held-out `fresh` set stays held out: none of its voices (with their options) or
    other words is in the calibration or test set, and no other word is an answer."""
    for language, voices in bench.VOICES["fresh"].items():
        for which in ("calibration", "test", "defaults"):
            assert not set(voices) & set(bench.VOICES[which].get(language, ()))
        words = {w.lower() for w in bench.OTHER_WORDS["fresh"][language]}
        for which in ("calibration", "test"):
            assert not words & {w.lower() for w in bench.OTHER_WORDS[which][language]}
        for app in bench.APPS:
            answers = {bench.spoken(b).lower() for _, buttons in bench.questions(app, language)
                       for b in buttons}
            assert not words & answers, app


def test_the_fresh2_set_shares_no_voice_variant_or_word_with_any_other_set(bench):
    """The second held-out set was fixed after the fresh set's misses were known: none of its
    voices, even at other speeds or pitches (the voice with its variant, options aside), is
    in any other set, none of its other words is in any other set or an answer, and it has
    voices and words in both languages."""
    for language, voices in bench.VOICES["fresh2"].items():
        names = {name.lower() for name, _ in voices}
        assert len(names) == len(voices) >= 7
        words = {w.lower() for w in bench.OTHER_WORDS["fresh2"][language]}
        assert len(words) == 20
        for which in set(bench.VOICES) - {"fresh2"}:
            theirs = {name.lower() for name, _ in bench.VOICES[which].get(language, ())}
            assert not names & theirs, which
            their_words = {w.lower() for w in bench.OTHER_WORDS[which].get(language, ())}
            assert not words & their_words, which
        for app in bench.APPS:
            answers = {bench.spoken(b).lower() for _, buttons in bench.questions(app, language)
                       for b in buttons}
            assert not words & answers, app
    assert set(bench.VOICES["fresh2"]) == {"en", "de"}


def test_the_defaults_set_is_the_by_hand_check_at_default_speed_and_pitch(bench):
    voices = bench.VOICES["defaults"]["en"]
    assert len(voices) == 8 and all(options == () for _, options in voices)
    assert {"en-gb-scotland", "en-029", "en-gb-x-rp"} <= {name for name, _ in voices}
