"""What seeing into a run costs: the survey with 10 people on the simulated clock (--fast), with
`--record`, with `--inspect` (a page polling it) and with both, against the same run without.

Prints per tick, for each set-up, the CPU time of this process (all its threads: the
inspector's server thread counts, the polling page runs in its own process like a browser)
as median and mean, and the wall time median, each as a ratio to the plain run measured in
the same process (rounds interleaved, so load changes hit all alike); the recording's size
per hour of robot time; and the load average. On a loaded machine the CPU figures are the
ones to trust: wall time then mostly measures waiting for a core.

    python benchmarks/bench_inspect.py [--minutes 3] [--people 10] [--rounds 3]

Benchmarks are not a layer: this script imports what it needs from every layer.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import subprocess
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_survey import scenario_text  # noqa: E402

from applications.graph.loader import load_application  # noqa: E402
from applications.inspect.server import Inspector  # noqa: E402
from applications.recording import Recorder, file_size_per_hour  # noqa: E402
from applications.runtime import Run  # noqa: E402
from behaviors.robot import open_robot  # noqa: E402

SETUPS = ("plain", "record", "inspect", "record+inspect")


def crowd_text(people: int, minutes: float) -> str:
    """All `people` in the hallway for the whole run, walking up and down it in lanes."""
    duration = minutes * 60
    lines = ["[scenario]", 'name = "crowd"', f"duration = {duration}", 'robot = "robot_home"', ""]
    for i in range(people):
        y = -0.1 + 0.1 * (i % 10)
        start, end = (-8.5, 8.5) if i % 2 == 0 else (8.5, -8.5)
        speed = 0.6 + 0.05 * i
        legs = int(duration * speed / 17) + 2
        waypoints = ", ".join(f"[{end if k % 2 == 0 else start}, {y:.1f}]" for k in range(legs))
        lines += ["[[person]]", f'id = "c{i}"', f"appear = {0.5 * i:.1f}",
                  f"at = [{start}, {y:.1f}]", f"speed = {speed:.2f}",
                  f"steps = [{{ walk = [{waypoints}] }}]", ""]
    return "\n".join(lines)


POLLER = """
import json, sys, urllib.request
base, token, seq, fetched = sys.argv[1], sys.argv[2], 0, 0
try:
    while True:
        with urllib.request.urlopen(f"{base}/api/snapshot?after={seq}&token={token}",
                                    timeout=10) as reply:
            seq = json.loads(reply.read()).get("seq", seq)
        fetched += 1
        print(fetched, flush=True)
except Exception:
    pass
"""


class Page:
    """Polls the inspector like the page does, from its own process (as a browser would)."""

    def __init__(self, url: str) -> None:
        base, token = url.split("/?")[0], url.split("token=")[1]
        self.process = subprocess.Popen([sys.executable, "-c", POLLER, base, token],
                                        stdout=subprocess.PIPE, text=True)
        self.fetched = 0

    def stop(self) -> None:
        self.process.terminate()
        out, _ = self.process.communicate(timeout=30)
        lines = out.split()
        self.fetched = int(lines[-1]) if lines else 0


def measure(setup: str, scenario: Path, minutes: float, folder: Path) -> dict:
    app = load_application("survey")
    robot = open_robot("horos", scenario=scenario, fast=True)
    observers, recorder, inspector, page = [], None, None, None
    if "record" in setup:
        recorder = Recorder(folder / f"{setup}.mcap", {"app": "survey", "robot": "horos",
                                                       "devices": []}, robot.top_view())
        observers.append(recorder)
    if "inspect" in setup:
        inspector = Inspector(app, address="0", robot="horos", map_=robot.top_view()).start()
        observers.append(inspector)
        page = Page(inspector.url)
    ticks: list[float] = []        # wall s per tick
    cpu: list[float] = []          # CPU s per tick, all threads of this process
    wait_until = robot.wait_until
    last = [time.perf_counter(), time.process_time()]

    def tick_boundary(t: float) -> None:
        now, now_cpu = time.perf_counter(), time.process_time()
        ticks.append(now - last[0])
        cpu.append(now_cpu - last[1])
        wait_until(t)
        last[0], last[1] = time.perf_counter(), time.process_time()

    robot.wait_until = tick_boundary
    try:
        summary = Run(app, robot, duration=minutes * 60, echo=None, observers=observers).run()
    finally:
        if page is not None:
            page.stop()
        if inspector is not None:
            inspector.close()
        if recorder is not None:
            recorder.close({"ticks": 0})
        robot.close()
    result = {"setup": setup, "ticks": summary.ticks,
              "median_ms": statistics.median(ticks) * 1e3,
              "cpu_median_ms": statistics.median(cpu) * 1e3,
              "cpu_mean_ms": statistics.fmean(cpu) * 1e3}
    if recorder is not None:
        result["mb_per_hour"] = file_size_per_hour(recorder.path, summary.ticks) / 1e6
    if page is not None:
        result["page_fetches"] = page.fetched
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=3.0)
    parser.add_argument("--people", type=int, default=10)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--crowd", action="store_true",
                        help="all the people in the hallway the whole time (default: they "
                             "arrive one by one, as in bench_survey.py)")
    args = parser.parse_args()
    results: dict[str, list[dict]] = {setup: [] for setup in SETUPS}
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        scenario = folder / "bench.toml"
        make = crowd_text if args.crowd else scenario_text
        scenario.write_text(make(args.people, args.minutes))
        for _ in range(args.rounds):
            for setup in SETUPS:
                results[setup].append(measure(setup, scenario, args.minutes, folder))
    load = os.getloadavg()
    print(f"survey, HOROS, {args.people} people{' all the time' if args.crowd else ''}, "
          f"{args.minutes:g} min of robot time, --fast, "
          f"{args.rounds} rounds; load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    base = {key: statistics.median(r[key] for r in results["plain"])
            for key in ("median_ms", "cpu_median_ms", "cpu_mean_ms")}
    for setup in SETUPS:
        runs = results[setup]
        values = {key: statistics.median(r[key] for r in runs) for key in base}
        extra = ""
        if "mb_per_hour" in runs[0]:
            extra += f"; recording {statistics.median(r['mb_per_hour'] for r in runs):.0f} MB/h"
        if "page_fetches" in runs[0]:
            extra += f"; page fetched {statistics.median(r['page_fetches'] for r in runs):.0f}x"
        print(f"  {setup:<15} CPU per tick: median {values['cpu_median_ms']:6.3f} ms "
              f"(ratio {values['cpu_median_ms'] / base['cpu_median_ms']:4.2f}), mean "
              f"{values['cpu_mean_ms']:6.3f} ms (ratio {values['cpu_mean_ms'] / base['cpu_mean_ms']:4.2f});"
              f" wall median {values['median_ms']:6.3f} ms "
              f"(ratio {values['median_ms'] / base['median_ms']:4.2f}){extra}")

if __name__ == "__main__":
    main()
