"""`interbot run --port URL` drives whatever is at the URL: here the P2OS emulator started by hand,
as a user without a Pioneer would do (`interbot emulate p2os --tcp 0`)."""
from __future__ import annotations

import re
import subprocess
import sys

from applications.cli import main
from applications.trace import read_trace


def test_run_over_a_tcp_port_to_a_separately_started_emulator(tmp_path, capsys):
    emulator = subprocess.Popen([sys.executable, "-m", "applications.cli", "emulate", "p2os",
                                 "--tcp", "0"], stdout=subprocess.PIPE, text=True)
    try:
        first_line = emulator.stdout.readline()
        url = re.search(r"socket://127\.0\.0\.1:\d+", first_line).group(0)
        trace = tmp_path / "port.jsonl"
        code = main(["run", "survey", "--robot", "horos", "--port", url, "--duration", "1.5",
                     "--trace", str(trace), "--data", str(tmp_path), "--quiet"])
    finally:
        emulator.terminate()
        emulator.wait(timeout=10)
    out = capsys.readouterr().out
    assert code == 0
    assert f"port {url}" in out and "in 15 ticks" in out
    events = read_trace(trace)
    assert [e["to"] for e in events if e["kind"] == "transition"] == ["Wait"]
    assert not any(e["kind"] == "fault" for e in events)
