"""How soon a misbehaving robot end receives a stop: `interbot run --port` against the scripted
P2OS robot end of tests/faults, with silent and garbling episodes injected.

For each episode it reports, from the fault's start (wall clock):
- `first_zero`: the first VEL 0 the robot end received (the keep-alive of a still robot counts:
  a zero is a zero);
- `way_out`: the last VEL 0 on the faulty connection, the driver's stop as it gives the link up.

    python benchmarks/bench_fault_stop.py [--episodes 6]

Prints medians and maxima, with the load average (the machine is shared).
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from tests.faults.conftest import WATCH_FAULTS_APP  # noqa: E402
from tests.faults.peer import ScriptedPioneer  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=6)
    args = parser.parse_args()
    peer = ScriptedPioneer()
    with tempfile.TemporaryDirectory() as tmp:
        app = Path(tmp) / "watch"
        app.mkdir()
        (app / "graph.xml").write_text(WATCH_FAULTS_APP)
        duration = 2 + args.episodes * 5
        process = subprocess.Popen(
            [sys.executable, "-m", "applications.cli", "run", str(app), "--robot", "horos",
             "--port", peer.url, "--duration", str(duration), "--data", tmp, "--quiet"],
            cwd=REPO, env=dict(os.environ, PYTHONPATH=str(REPO)),
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        peer.wait_open(20)
        results = []
        for episode in range(args.episodes):
            time.sleep(1.5)
            mode = ("silent", "garbage")[episode % 2]
            conn, start = peer.connections, time.monotonic()
            peer.mode = mode
            time.sleep(1.5)
            peer.mode = "normal"
            zeros = [r.t - start for r in list(peer.received)
                     if r.conn == conn and r.t >= start and r.name == "VEL 0"]
            results.append((mode, zeros[0] if zeros else None, zeros[-1] if zeros else None))
            peer.wait_for(lambda: peer.connections > conn and peer._open, timeout=10)
        process.terminate()
        process.wait(timeout=20)
    peer.shutdown()
    for name, index in (("first_zero", 1), ("way_out", 2)):
        values = [r[index] for r in results if r[index] is not None]
        missing = len(results) - len(values)
        print(f"{name:10} median {statistics.median(values) * 1000:5.0f} ms  max "
              f"{max(values) * 1000:5.0f} ms  (n={len(values)}, no stop: {missing})")
    print(f"load average: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
