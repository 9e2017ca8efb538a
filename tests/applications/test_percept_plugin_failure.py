"""A percept plugin that raises while an application runs: only its percepts and the conditions
that read them are off, one line names the plugin, the trace records it, the rest runs."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from applications.conditions import compile_condition
from applications.statemachine import StateMachine
from applications.graph.loader import load_application
from behaviors.percepts import PerceptView

ROOT = Path(__file__).resolve().parents[2]

PLUGIN = '''
from behaviors.percepts import PerceptProvider, spec

def read(ctx):
    raise KeyError("people/nearby")

SPEC = PerceptProvider("wobbly", (spec("wobbly.near", "bool", doc="someone near"),), read)
'''

GRAPH = '''<application name="wobbly_app" initial="Wait" robot="horos">
  <state name="Wait" behavior="Idle">
    <transition to="Wrong" when="not wobbly.near" priority="1"/>
    <transition to="Done" when="time_in_state > 2s" priority="2"/>
  </state>
  <state name="Wrong" behavior="Idle"/>
  <state name="Done" behavior="Idle" final="true"/>
</application>
'''


def install_broken_plugin(site: Path) -> dict:
    """A package whose percept provider loads fine and raises on every read, registered by an
    entry point in a folder of its own (what `pip install` would leave)."""
    site.mkdir(parents=True)
    (site / "wobbly_plugin.py").write_text(PLUGIN)
    info = site / "interbot_wobbly-0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: interbot-wobbly\nVersion: 0\n")
    (info / "entry_points.txt").write_text("[interbot.percepts]\nwobbly = wobbly_plugin:SPEC\n")
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}


def cli(*args: str, env: dict) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "applications.cli", *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=300, env=env)


def test_a_condition_reading_a_disabled_percept_is_off_whatever_its_form():
    view = PerceptView({"user.present": None, "people.count": 1}, 0.0,
                       frozenset({"user.present"}))
    assert not compile_condition("not user.present").evaluate(view, 0.0)
    assert not compile_condition("not user.present or time_in_state > 1s").evaluate(view, 5.0)
    assert compile_condition("people.count >= 1").evaluate(view, 0.0)
    assert compile_condition("time_in_state > 1s").evaluate(view, 5.0)
    plain = PerceptView({"user.present": None}, 0.0)
    assert compile_condition("not user.present").evaluate(plain, 0.0)


def test_the_state_machine_skips_a_transition_that_reads_a_disabled_percept():
    machine = StateMachine(load_application("survey"), now=0.0)
    machine.step({"people.new": 1}, now=31.0)               # into CreateAttention
    off = PerceptView({"user.present": None, "user.distance": None}, 32.0,
                      frozenset({"user.present", "user.distance"}))
    assert machine.step(off, now=32.0) is None              # "person left" must not fire
    assert machine.state.name == "CreateAttention"


def test_a_plugin_raising_at_run_time_disables_only_what_reads_it(tmp_path):
    env = install_broken_plugin(tmp_path / "site")
    app = tmp_path / "wobbly_app"
    app.mkdir()
    (app / "graph.xml").write_text(GRAPH)
    (app / "dialog.xml").write_text("<dialog/>\n")
    trace = tmp_path / "run.jsonl"
    ran = cli("run", str(app), "--fast", "--duration", "6", "--trace", str(trace),
              "--data", str(tmp_path / "data"), env=env)
    assert ran.returncode == 0, ran.stdout + ran.stderr
    named = [line for line in ran.stdout.splitlines() if "PERCEPT PLUGIN 'wobbly'" in line]
    assert len(named) == 2          # the moment it failed, and again in the summary
    assert "KeyError: 'people/nearby'" in named[0] and "wobbly.near are disabled" in named[0]
    assert "Wait -> Wrong (graph.xml:3)" in named[0]
    events = [json.loads(line) for line in trace.read_text().splitlines()]
    [failed] = [e for e in events if e["kind"] == "plugin"]
    assert failed["plugin"] == "wobbly" and failed["percepts"] == ["wobbly.near"]
    assert failed["off"] == ["Wait -> Wrong (graph.xml:3)"]
    moves = [(e["from"], e["to"]) for e in events if e["kind"] == "transition"]
    assert moves == [(None, "Wait"), ("Wait", "Done")]


def test_the_bundled_survey_runs_beside_a_plugin_that_raises(tmp_path):
    env = install_broken_plugin(tmp_path / "site")
    ran = cli("run", "survey", "--fast", "--quiet", "--duration", "40",
              "--data", str(tmp_path / "data"), env=env)
    assert ran.returncode == 0, ran.stdout + ran.stderr
    assert "PERCEPT PLUGIN 'wobbly' FAILED (KeyError: 'people/nearby')" in ran.stdout
    assert "no condition of the application reads them" in ran.stdout
    assert "ran 40.0 s of robot time" in ran.stdout
