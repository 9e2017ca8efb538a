"""Every way out of a run stops and closes the base first, then reports one line (no traceback)
with an exit code of its own: an exception in a skill, a driver, the state machine or the trace
writer; and a reader that closed our stdout ends the run quietly."""
from __future__ import annotations

import importlib
import os
import subprocess
import sys

import pytest

from applications.cli import main
from applications.shutdown import EXIT_BROKEN_PIPE, EXIT_CRASH, EXIT_OUTPUT
from tests.faults.conftest import REPO


def raise_after(calls: int, exc: BaseException):
    """A stand-in that works `calls` times (through `original`) and then raises `exc`."""
    count = {"n": 0}

    def install(original):
        def replacement(*args, **kwargs):
            count["n"] += 1
            if count["n"] > calls:
                raise exc
            return original(*args, **kwargs)
        return replacement
    return install


def run_in_process(peer, app, tmp_path, capsys):
    code = main(["run", str(app), "--robot", "horos", "--port", peer.url, "--duration", "5",
                 "--trace", str(tmp_path / "trace.jsonl"), "--data", str(tmp_path / "data")])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def assert_stopped_and_closed(peer) -> None:
    tail = peer.names()[-3:]
    assert tail == ["VEL 0", "RVEL 0", "CLOSE"], peer.names()[-6:]


@pytest.mark.parametrize("target,component", [
    # What the layer calls inside itself is made to fail, so the failure is in the layer's code.
    ("skills.obstacles:ObstacleSensing._free_ahead_sonar", "the obstacles skill"),
    ("robots.p2os.driver:clamp_velocity", "the p2os driver"),
    ("applications.statemachine:StateMachine.time_in_state", "the state machine"),
])
def test_an_exception_in_a_layer_stops_and_closes_the_base_then_one_line(
        peer, watch_app, tmp_path, capsys, monkeypatch, target, component):
    module_name, _, attr = target.partition(":")
    owner = importlib.import_module(module_name)
    *path, name = attr.split(".")
    for part in path:
        owner = getattr(owner, part)
    monkeypatch.setattr(owner, name, raise_after(5, RuntimeError("injected"))(getattr(owner, name)))
    code, out, err = run_in_process(peer, watch_app, tmp_path, capsys)
    assert code == EXIT_CRASH
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert component in lines[0] and "RuntimeError: injected" in lines[0]
    assert "stopped and closed" in lines[0]
    assert_stopped_and_closed(peer)
    assert "ended early by an error" in out
    trace = (tmp_path / "trace.jsonl").read_text().splitlines()
    assert '"kind": "crash"' in trace[-1]


def test_a_failing_trace_writer_stops_and_closes_the_base_then_one_line(
        peer, watch_app, tmp_path, capsys, monkeypatch):
    from applications.trace import TraceWriter
    original = TraceWriter.__init__

    def onto_a_full_disk(self, path):       # the disk fills up after the arguments were checked
        original(self, path)
        self._file.close()
        self._file = open("/dev/full", "w", encoding="utf-8")
    monkeypatch.setattr(TraceWriter, "__init__", onto_a_full_disk)
    code, out, err = run_in_process(peer, watch_app, tmp_path, capsys)
    assert code == EXIT_OUTPUT
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "the trace writer" in lines[0] and "No space left" in lines[0]
    assert_stopped_and_closed(peer)


def test_a_closed_stdout_ends_the_run_quietly():
    # --no-progress: the once-a-second progress lines on stderr are not what this is about;
    # on a loaded machine the next stdout write came after three of them (a flake)
    process = subprocess.Popen([sys.executable, "-m", "applications.cli", "run", "survey",
                                "--fast", "--no-progress", "--data", "interbot-data-pipe-test"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=REPO,
                               env=dict(os.environ, PYTHONPATH=str(REPO)))
    try:
        first = process.stdout.readline()
        process.stdout.close()                     # `| head -1`
        err = process.stderr.read().decode()
        code = process.wait(timeout=120)
    finally:
        if process.poll() is None:
            process.kill()
        import shutil
        shutil.rmtree(REPO / "interbot-data-pipe-test", ignore_errors=True)
    assert first.startswith(b"interbot: running")
    assert err == ""
    assert code == EXIT_BROKEN_PIPE


def test_an_answer_database_that_fails_ends_the_run_with_one_line(tmp_path, capsys, monkeypatch):
    """The answers cannot be written (disk gone): exit 5, one line, the summary still printed."""
    from applications.database import AnswerDatabase
    original = AnswerDatabase.__init__

    def that_fails_later(self, path, schema_file):
        original(self, path, schema_file)
        self._db.close()                      # every later write raises sqlite3.ProgrammingError
    monkeypatch.setattr(AnswerDatabase, "__init__", that_fails_later)
    monkeypatch.setattr(AnswerDatabase, "close", lambda self: None)
    code = main(["run", "survey", "--scenario", "complete", "--fast", "--quiet",
                 "--data", str(tmp_path / "data")])
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert code == EXIT_OUTPUT
    assert len(lines) == 1 and "the answer database" in lines[0], captured.err
    assert "ended early by an error" in captured.out
