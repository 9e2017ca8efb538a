"""Recording a run to MCAP, reading it back (also after kill -9), and replaying it."""
from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import jsonschema
import pytest
from mcap.reader import make_reader

from applications.cli import main
from applications.exceptions import ApplicationError
from applications.foxglove_messages import TOPICS as FOXGLOVE_TOPICS
from applications.graph.loader import find_application
from applications.recording import (CHUNK_SIZE, SCHEMAS, Recording, open_recording, read_ticks)
from applications.replay import ReplayFeed
from applications.tracetools import summarize
from tests.processes import faulthandler_env, finish

SURVEY = find_application("survey")


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """The survey's `complete` scenario for 60 s on the simulated clock, recorded, with its
    JSON-lines trace beside it."""
    folder = tmp_path_factory.mktemp("recorded")
    path, trace = folder / "run.mcap", folder / "run.jsonl"
    status = main(["run", "survey", "--scenario", "complete", "--fast", "--duration", "60",
                   "--quiet", "--no-progress", "--record", str(path), "--trace", str(trace),
                   "--data", str(folder / "data")])
    assert status == 0
    return path, trace


def test_every_topic_has_a_declared_json_schema_and_every_message_follows_it(recorded):
    path, _ = recorded
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        topics = {channel.topic: summary.schemas[channel.schema_id]
                  for channel in summary.channels.values()}
        assert set(topics) == set(SCHEMAS) | set(FOXGLOVE_TOPICS)
        for schema in topics.values():
            assert schema.encoding == "jsonschema"
            jsonschema.Draft7Validator.check_schema(json.loads(schema.data))
        checked, validators = 0, {}
        for schema, channel, message in reader.iter_messages():
            assert channel.message_encoding == "json"
            if schema.id not in validators:   # one validator per schema (its draft), checked once
                document = json.loads(schema.data)
                validators[schema.id] = jsonschema.validators.validator_for(document)(document)
            validators[schema.id].validate(json.loads(message.data))
            checked += 1
    assert checked == summary.statistics.message_count > 600 * 9


def test_a_recording_holds_each_tick_with_inputs_decisions_and_metadata(recorded):
    path, trace = recorded
    recording = Recording(path)
    ticks = list(read_ticks(recording))
    assert len(ticks) == 601 and not recording.truncated
    assert recording.meta["app"] == "survey" and recording.meta["robot"] == "horos"
    assert recording.meta["devices"] == ["laser", "people_detector", "head", "screen", "speaker"]
    assert recording.meta["duration"] == 60.0 and recording.end["ticks"] == 601
    assert recording.map["walls"] and recording.map["robot"]["radius"] > 0
    # the transitions of the recording are exactly those of the run's trace
    events = [json.loads(line) for line in trace.read_text().splitlines()]
    traced = [(e["from"], e["to"]) for e in events if e["kind"] == "transition"]
    recorded_transitions = [(m["/interbot/tick"]["transition"]["from"],
                             m["/interbot/tick"]["transition"]["to"])
                            for m in ticks if m["/interbot/tick"]["transition"]]
    assert recorded_transitions == traced
    middle = ticks[450]
    inputs = [key for key, _ in middle["/interbot/inputs"]["inputs"]]
    assert {"sense", "now", "base.read_state", "laser.read", "detector.detect"} <= set(inputs)
    assert "base.command" in [key for key, _ in middle["/interbot/hardware"]["commands"]]
    assert middle["/interbot/behaviors"]["tree"]["status"] in ("RUNNING", "SUCCESS", "FAILURE")
    assert "user.distance" in middle["/interbot/behaviors"]["percepts"]
    assert "localization" in middle["/interbot/skills"]["skills"]


def test_a_recorded_run_replays_without_divergence(recorded, capsys):
    path, _ = recorded
    assert main(["replay", str(path)]) == 0
    out = capsys.readouterr().out
    assert "no divergence in 601 ticks" in out


def test_a_run_on_a_given_map_and_start_pose_replays_on_them(tmp_path, capsys, monkeypatch):
    # localization decides the robot's pose: the replay must start it where the run did
    import behaviors.robot
    opened, real = [], behaviors.robot.open_robot

    def spy(*args, **kwargs):
        opened.append(real(*args, **kwargs))
        return opened[-1]
    monkeypatch.setattr(behaviors.robot, "open_robot", spy)
    path = tmp_path / "run.mcap"
    assert main(["run", "survey", "--scenario", "complete", "--fast", "--duration", "8",
                 "--quiet", "--no-progress", "--record", str(path), "--data", str(tmp_path),
                 "--map", "office", "--initial-pose", "0.2,-0.6,80"]) == 0
    meta = open_recording(path).meta
    assert meta["map"] == "office"
    assert meta["initial_pose"] == pytest.approx([0.2, -0.6, math.radians(80)])
    capsys.readouterr()
    assert main(["replay", str(path)]) == 0
    assert "no divergence in 81 ticks" in capsys.readouterr().out
    run, replay = (robot.skills for robot in opened)
    assert replay.localization.initial_pose == run.localization.initial_pose
    assert replay.localization.initial_pose == pytest.approx((0.2, -0.6, math.radians(80)))
    assert replay.map.name == "office"


def test_a_changed_application_shows_the_first_divergence(recorded, tmp_path, capsys):
    path, trace = recorded
    changed = tmp_path / "survey_changed"
    shutil.copytree(SURVEY, changed)
    graph = changed / "graph.xml"
    text = graph.read_text()
    closer = text.replace('when="user.distance &lt; 0.75m"', 'when="user.distance &lt; 0.6m"')
    assert closer != text
    graph.write_text(closer)
    assert main(["replay", str(path), "--app", str(changed)]) == 1
    out = capsys.readouterr().out
    events = [json.loads(line) for line in trace.read_text().splitlines()]
    entered = next(e["t"] for e in events if e["kind"] == "transition" and e["to"] == "Interaction")
    tick = round(entered / 0.1)
    assert (f"first divergence at tick {tick} (t = {entered:.1f} s): state was Interaction when "
            f"recorded, CreateAttention in the replay") in out
    # and why: the condition that held in the recording and not in the replay, with the value
    recorded = [m for m in read_ticks(path) if m["/interbot/tick"]["tick"] == tick][0]
    distance = recorded["/interbot/behaviors"]["percepts"]["user.distance"]["value"]
    assert 0.6 <= distance < 0.75
    assert ("  recorded  CreateAttention -> Interaction when user.distance < 0.75m: held\n"
            "  replay    CreateAttention -> Interaction when user.distance < 0.6m: did not hold\n"
            "  percepts they read, recorded / replay:\n"
            f"    user.distance = {distance:.3f} / {distance:.3f}\n") in out


def test_summary_of_the_recording_and_of_the_trace_agree(recorded):
    path, trace = recorded
    from_recording, from_trace = summarize(path), summarize(trace)
    assert from_recording.transitions == from_trace.transitions
    assert from_recording.answers == from_trace.answers == [
        (pytest.approx(t), q, a) for t, q, a in from_trace.answers]
    assert len(from_recording.answers) == 3
    assert from_recording.min_clearance is not None and from_recording.min_clearance < 0.5
    assert from_trace.min_clearance is None
    assert sum(from_recording.time_in_state.values()) == pytest.approx(60.1)


def test_a_file_that_is_not_a_recording_is_refused_with_its_name(tmp_path):
    bogus = tmp_path / "bogus.mcap"
    bogus.write_bytes(b"this is not mcap at all")
    with pytest.raises(ApplicationError, match="bogus.mcap is not a readable MCAP recording"):
        open_recording(bogus)


def test_after_kill_9_the_recording_is_readable_up_to_its_last_chunk(tmp_path):
    """A long --fast run killed while recording: everything up to the last chunk written
    reads back, at most one chunk (under 1 MiB) is lost, and the part replays cleanly."""
    path = tmp_path / "killed.mcap"
    process = subprocess.Popen(
        [sys.executable, "-m", "applications.cli", "run", "survey", "--fast", "--duration",
         "3600", "--quiet", "--no-progress", "--record", str(path), "--data", str(tmp_path)],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=tmp_path)
    try:
        deadline = time.monotonic() + 240
        while (not path.exists() or path.stat().st_size < 3 * CHUNK_SIZE // 4) \
                and time.monotonic() < deadline and process.poll() is None:
            time.sleep(0.2)
        assert process.poll() is None, process.stderr.read().decode()
    finally:
        process.send_signal(signal.SIGKILL)
        process.wait()
    assert process.returncode == -signal.SIGKILL
    recording = Recording(path)
    ticks = [m["/interbot/tick"]["tick"] for m in read_ticks(recording)]
    assert recording.truncated
    assert ticks == list(range(len(ticks))) and len(ticks) > 10
    assert os.path.getsize(path) - recording.good_bytes <= 1024 * 1024
    assert recording.meta["duration"] == 3600.0
    feed = ReplayFeed(recording)
    assert feed.devices == recording.meta["devices"]
    result = subprocess.run([sys.executable, "-m", "applications.cli", "replay", str(path)],
                            capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert f"the recording ends before tick {len(ticks)}" in result.stdout
    assert f"no divergence in {len(ticks)} ticks" in result.stdout


def test_trace_command_draws_the_time_line_and_the_path(recorded, tmp_path, capsys):
    from lxml import etree

    path, trace = recorded
    timeline, route = tmp_path / "states.svg", tmp_path / "path.svg"
    assert main(["trace", str(path), "--timeline", str(timeline), "--path", str(route)]) == 0
    out = capsys.readouterr().out
    assert "time per state:" in out and "minimum clearance to people:" in out
    bars = etree.parse(str(timeline)).getroot().findall(".//{http://www.w3.org/2000/svg}rect")
    states = [bar.get("data-state") for bar in bars if bar.get("class") == "state"]
    assert states == ["Wait", "CreateAttention", "Interaction", "Wait"]
    lines = etree.parse(str(route)).getroot().findall(".//{http://www.w3.org/2000/svg}polyline")
    kinds = {line.get("class") for line in lines}
    assert {"robot", "track", "truth"} <= kinds
    assert main(["trace", str(trace), "--path", str(tmp_path / "nope.svg")]) == 1
    assert "a trace has no poses" in capsys.readouterr().err


def test_pictures_are_written_in_the_format_their_name_asks_for(recorded, tmp_path, capsys):
    from PIL import Image

    path, _ = recorded
    timeline, route = tmp_path / "states.png", tmp_path / "path.pdf"
    assert main(["trace", str(path), "--timeline", str(timeline), "--path", str(route)]) == 0
    with Image.open(timeline) as picture:
        assert picture.format == "PNG" and picture.size == (900, 148)
        colours = {colour for _, colour in picture.convert("RGB").getcolors(1 << 20)}
    assert (0x1f, 0x77, 0xb4) in colours and (0xff, 0x7f, 0x0e) in colours   # Wait, CreateAttention
    assert route.read_bytes().startswith(b"%PDF-")
    capsys.readouterr()
    with pytest.raises(SystemExit) as refused:      # a mistaken argument (issue 24): exit 2
        main(["trace", str(path), "--timeline", str(tmp_path / "states.gif")])
    assert refused.value.code == 2
    assert "states.gif: cannot draw a '.gif' file (the format comes from the name); allowed " \
           "OUT.svg, OUT.png, OUT.pdf" in capsys.readouterr().err
    assert not (tmp_path / "states.gif").exists()


def test_a_real_port_run_on_the_real_clock_records_and_replays_without_divergence(tmp_path, capsys):
    """Over a TCP port to the P2OS emulator (as on a robot: real clock, no ground truth, no
    map), the recording holds the base's readings and replays tick for tick."""
    import re

    from tests.applications.test_real_port import BASE_ONLY_APP

    emulator = subprocess.Popen([sys.executable, "-m", "applications.cli", "emulate", "p2os",
                                 "--tcp", "0"], stdout=subprocess.PIPE, text=True)
    try:
        url = re.search(r"socket://127\.0\.0\.1:\d+", emulator.stdout.readline()).group(0)
        app = tmp_path / "pause"
        app.mkdir()
        (app / "graph.xml").write_text(BASE_ONLY_APP)
        path = tmp_path / "port.mcap"
        assert main(["run", str(app), "--robot", "horos", "--port", url, "--duration", "5",
                     "--data", str(tmp_path), "--quiet", "--record", str(path)]) == 0
    finally:
        emulator.terminate()
        emulator.wait(timeout=10)
    recording = Recording(path)
    ticks = list(read_ticks(recording))
    assert recording.meta["port"] == url and recording.meta["devices"] == ["speaker"]
    assert recording.map["walls"] == [] and len(recording.map["robot"]["sonar"]) == 16
    assert all(m["/interbot/hardware"]["truth"] == [] for m in ticks)
    assert all(len(m["/interbot/hardware"]["base"]["sonar"]) == 16 for m in ticks)
    assert ticks[-1]["/interbot/tick"]["state"] == "Done"
    capsys.readouterr()
    assert main(["replay", str(path)]) == 0
    assert f"no divergence in {len(ticks)} ticks" in capsys.readouterr().out


def _ignoring_sigint():
    """What a parent that ignores Ctrl-C (a job started with `nohup`, some test runners)
    passes on: SIGINT ignored, so Python installs no KeyboardInterrupt of its own."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@pytest.mark.parametrize("signum, ignored_at_start", [(signal.SIGTERM, False),
                                                      (signal.SIGINT, True)],
                         ids=["SIGTERM", "SIGINT-ignored-by-the-parent"])
def test_a_replay_left_on_its_last_tick_ends_cleanly_on_a_signal(recorded, signum,
                                                                  ignored_at_start):
    path, _ = recorded
    process = subprocess.Popen([sys.executable, "-m", "applications.cli", "replay", str(path),
                                "--inspect", "0", "--speed", "20"], env=faulthandler_env(),
                               preexec_fn=_ignoring_sigint if ignored_at_start else None,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = ""
        while "the replay is over" not in line:
            line = process.stdout.readline()
            assert line, process.stderr.read()
    finally:
        process.send_signal(signum)
        rest, err = finish(process, timeout=60)
    assert process.returncode == 0, err
    assert "no divergence in 601 ticks" in rest        # closed as after any replay


def test_replay_with_the_inspector_pauses_and_steps_one_tick(recorded):
    import urllib.request

    path, _ = recorded
    process = subprocess.Popen([sys.executable, "-m", "applications.cli", "replay", str(path),
                                "--inspect", "0", "--speed", "20"], env=faulthandler_env(),
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def call(query: str, method: str = "GET") -> dict:
        request = urllib.request.Request(f"{base}/api/{query}&token={token}", method=method)
        with urllib.request.urlopen(request, timeout=30) as reply:
            return json.loads(reply.read())

    try:
        url = None
        while url is None:
            line = process.stdout.readline()
            assert line, process.stderr.read()
            if "inspector at " in line:
                url = line.split("inspector at ")[1].strip()
        base, token = url.split("/?")[0], url.split("token=")[1]
        assert call("control?action=pause", "POST")["paused"]
        held = call("snapshot?after=0")
        for _ in range(5):       # the pause holds the loop at its next tick
            again = call(f"snapshot?after={held['seq']}")    # waits a second if nothing new
            if again["seq"] == held["seq"]:
                break
            held = again
        assert again["seq"] == held["seq"] and again["paused"]
        call("control?action=step", "POST")
        stepped = call(f"snapshot?after={held['seq']}")
        assert stepped["seq"] == held["seq"] + 1
        assert stepped["snapshot"]["tick"] == held["snapshot"]["tick"] + 1
        call("control?action=resume", "POST")
        out = []
        while not any("the replay is over" in line for line in out):
            line = process.stdout.readline()
            assert line, process.stderr.read()
            out.append(line)
    finally:
        process.send_signal(signal.SIGINT)
        rest, _ = finish(process, timeout=60)
    assert process.returncode == 0
    assert "no divergence in 601 ticks" in rest
