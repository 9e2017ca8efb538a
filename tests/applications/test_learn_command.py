"""A run with a choice point writes its choice and outcome to the trace and the learner's
statistics; `interbot learn` reports them, draws the curve, freezes and resets."""
import json

from applications.cli import build_parser, main
from applications.commands.learn import LearnCommand
from applications.tracetools import ticks_of
from tests.applications.learning_app import survey_with_choice


def learn(*argv) -> int:
    args = build_parser({"learn": LearnCommand()}).parse_args(["learn", *map(str, argv)])
    return args.handler.run(args)


def test_a_run_records_its_choice_and_learn_reports_it(tmp_path, capsys):
    folder = survey_with_choice(tmp_path / "app", by="rotate")
    data, trace = tmp_path / "data", tmp_path / "trace.jsonl"
    recording = tmp_path / "run.mcap"
    assert main(["run", str(folder), "--fast", "--quiet", "--scenario", "complete",
                 "--data", str(data), "--trace", str(trace), "--duration", "60",
                 "--record", str(recording)]) == 0
    events = [json.loads(line) for line in trace.read_text().splitlines()]
    choices = [e for e in events if e["kind"] in ("choice", "outcome")]
    assert [(e["kind"], e["alternative"]) for e in choices] == [("choice", "face"),
                                                               ("outcome", "face")]
    assert choices[1]["success"] is True and choices[0]["by"] == "rotate"
    recorded = [e for tick in ticks_of(recording) for e in tick.get("events", [])
                if e["kind"] in ("choice", "outcome")]
    assert recorded == choices                      # the recording has them too
    capsys.readouterr()
    assert learn(folder, "--data", data, "--curve", tmp_path / "curve.svg") == 0
    out = capsys.readouterr().out
    assert "choice point attract (state CreateAttention, by rotate" in out
    assert "face             trials     1  successes     1" in out
    assert "call             trials     0" in out
    assert (tmp_path / "curve.svg").read_text().startswith("<svg")
    assert learn(folder, "--data", data, "--freeze") == 0
    assert "[FROZEN: exploit only]" in capsys.readouterr().out
    assert learn(folder, "--data", data, "--point", "attract", "--reset") == 0
    out = capsys.readouterr().out
    assert "reset attract: forgot 1 episode(s)" in out and "no episodes yet" in out
