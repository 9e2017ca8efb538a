"""`interbot run --port URL` drives whatever is at the URL: here the P2OS emulator started by hand,
as a user without a Pioneer would do (`interbot emulate p2os --tcp 0`). On a real robot only the
base is driven by itself, so an application needing the touch screen is refused before it moves
unless `--gui` serves the tablet page."""
from __future__ import annotations

import re
import subprocess
import sys

import pytest

from applications.cli import main
from applications.trace import read_trace

BASE_ONLY_APP = """<application name="pause" initial="Wait" robot="horos">
  <state name="Wait" behavior="Idle">
    <transition to="Done" when="time_in_state > 1s"/>
  </state>
  <state name="Done" behavior="Idle" final="true"/>
</application>
"""


@pytest.fixture
def emulator_url():
    emulator = subprocess.Popen([sys.executable, "-m", "applications.cli", "emulate", "p2os",
                                 "--tcp", "0"], stdout=subprocess.PIPE, text=True)
    try:
        yield re.search(r"socket://127\.0\.0\.1:\d+", emulator.stdout.readline()).group(0)
    finally:
        emulator.terminate()
        emulator.wait(timeout=10)


def test_run_over_a_tcp_port_to_a_separately_started_emulator(tmp_path, capsys, emulator_url):
    app = tmp_path / "pause"
    app.mkdir()
    (app / "graph.xml").write_text(BASE_ONLY_APP)
    trace = tmp_path / "port.jsonl"
    code = main(["run", str(app), "--robot", "horos", "--port", emulator_url, "--duration", "5",
                 "--trace", str(trace), "--data", str(tmp_path), "--quiet"])
    out = capsys.readouterr().out
    assert code == 0
    assert f"port {emulator_url}" in out
    events = read_trace(trace)
    assert [e["to"] for e in events if e["kind"] == "transition"] == ["Wait", "Done"]
    assert not any(e["kind"] == "fault" for e in events)


def test_the_survey_is_refused_before_moving_when_the_screen_is_not_driven(tmp_path, capsys,
                                                                           emulator_url):
    code = main(["run", "survey", "--robot", "horos", "--port", emulator_url, "--duration", "1",
                 "--data", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert "'Survey' cannot run" in err[0] and "touch_screen" in err[0]


def test_with_the_tablet_page_the_survey_runs_on_a_real_port(tmp_path, capsys, emulator_url):
    trace = tmp_path / "gui.jsonl"
    code = main(["run", "survey", "--robot", "horos", "--port", emulator_url, "--duration", "2",
                 "--gui", "127.0.0.1:0", "--speech-wav", str(tmp_path / "speech"),
                 "--trace", str(trace), "--data", str(tmp_path), "--quiet"])
    out = capsys.readouterr().out
    assert code == 0
    assert re.search(r"tablet page at http://127\.0\.0\.1:\d+/\?token=[\w-]{16,}", out)
    events = read_trace(trace)
    assert [e["to"] for e in events if e["kind"] == "transition"] == ["Wait"]
    assert not any(e["kind"] == "fault" for e in events)
