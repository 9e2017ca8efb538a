"""`--listen` (issue 25 point 2): the microphone without a value, WAV files with one; the
language and voice the run chose reach the hardware."""
import argparse

from applications.commands.run import add_interaction_arguments, interaction_options


def parse(*argv):
    parser = argparse.ArgumentParser()
    add_interaction_arguments(parser)
    return parser.parse_args(list(argv))


def test_listen_alone_is_the_microphone_and_with_a_path_the_files():
    assert interaction_options(parse("--listen"))["listen"] is True
    assert interaction_options(parse("--listen", "answers/"))["listen"] == "answers/"
    assert interaction_options(parse())["listen"] is False


def test_the_runs_language_and_the_dialogs_voice_reach_the_hardware_unless_given():
    options = interaction_options(parse(), "de", None)
    assert options["language"] == "de" and options["voice"] is None
    assert interaction_options(parse(), "en", "en-us+f3")["voice"] == "en-us+f3"
    assert interaction_options(parse("--voice", "en+m3"), "en", "en-us+f3")["voice"] == "en+m3"
