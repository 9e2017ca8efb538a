"""What `--record` costs per tick and how many MB an hour of robot time takes: the survey with
people arriving (as in bench_survey.py) on the simulated clock, without a recorder and with the
recorder as it was before Foxglove's views and as it is now, and with the Foxglove live view
that nobody watches.

Set-ups, each round in this order, rounds interleaved so load changes hit all alike:
  plain        no recorder
  before       the recorder without message indexes, Foxglove topics or laser byte planes
               (what --record wrote before those three)
  foxglove     with message indexes and Foxglove's 3D topics, laser arrays as they come
  after        all three (what --record writes now)
  live         no recorder, `--foxglove` serving with nobody connected

Prints, per set-up, the CPU time per tick of this process (median and mean) as a ratio to the
plain run measured in the same process, and the recording's size scaled to an hour of robot
time (file size / ticks x 36 000).

    python benchmarks/bench_recording.py [--minutes 3] [--people 10] [--rounds 3]

Benchmarks are not a layer: this script imports what it needs from every layer.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_survey import scenario_text  # noqa: E402

from applications.foxglove_live import FoxgloveLive  # noqa: E402
from applications.graph.loader import load_application  # noqa: E402
from applications.recording import Recorder, file_size_per_hour  # noqa: E402
from applications.runtime import Run  # noqa: E402
from behaviors.robot import open_robot  # noqa: E402

SETUPS = {
    "plain": None,
    "before": {"well_known": False, "message_indexes": False, "planes": False},
    "foxglove": {"well_known": True, "message_indexes": True, "planes": False},
    "after": {"well_known": True, "message_indexes": True, "planes": True},
    "live": None,
}


def measure(setup: str, scenario: Path, minutes: float, folder: Path) -> dict:
    app = load_application("survey")
    robot = open_robot("horos", scenario=scenario, fast=True)
    recorder = live = None
    if SETUPS[setup] is not None:
        recorder = Recorder(folder / f"{setup}.mcap", {"app": "survey", "robot": "horos",
                                                       "devices": []}, robot.top_view(),
                            **SETUPS[setup])
    if setup == "live":
        live = FoxgloveLive("0", layout=robot.top_view(), name="bench")
    observers = [o for o in (recorder, live) if o is not None]
    cpu: list[float] = []          # CPU s per tick, this process
    wait_until = robot.wait_until
    last = [time.process_time()]

    def tick_boundary(t: float) -> None:
        now = time.process_time()
        cpu.append(now - last[0])
        wait_until(t)
        last[0] = time.process_time()

    robot.wait_until = tick_boundary
    try:
        summary = Run(app, robot, duration=minutes * 60, echo=None, observers=observers).run()
    finally:
        if recorder is not None:
            recorder.close({"ticks": 0})
        if live is not None:
            live.close()
        robot.close()
    result = {"ticks": summary.ticks, "cpu_median_ms": statistics.median(cpu) * 1e3,
              "cpu_mean_ms": statistics.fmean(cpu) * 1e3}
    if recorder is not None:
        result["mb_per_hour"] = file_size_per_hour(recorder.path, summary.ticks) / 1e6
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=3.0)
    parser.add_argument("--people", type=int, default=10)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    results: dict[str, list[dict]] = {setup: [] for setup in SETUPS}
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        scenario = folder / "bench.toml"
        scenario.write_text(scenario_text(args.people, args.minutes))
        for _ in range(args.rounds):
            for setup in SETUPS:
                results[setup].append(measure(setup, scenario, args.minutes, folder))
    load = os.getloadavg()
    print(f"survey, HOROS, {args.people} people arriving, {args.minutes:g} min of robot time, "
          f"--fast, {args.rounds} rounds; load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    base = {key: statistics.median(r[key] for r in results["plain"])
            for key in ("cpu_median_ms", "cpu_mean_ms")}
    for setup, runs in results.items():
        median = statistics.median(r["cpu_median_ms"] for r in runs)
        mean = statistics.median(r["cpu_mean_ms"] for r in runs)
        size = (f"; {statistics.median(r['mb_per_hour'] for r in runs):6.1f} MB per hour"
                if "mb_per_hour" in runs[0] else "")
        print(f"  {setup:<9} CPU per tick: median {median:6.3f} ms (ratio "
              f"{median / base['cpu_median_ms']:4.2f}), mean {mean:6.3f} ms (ratio "
              f"{mean / base['cpu_mean_ms']:4.2f}){size}")


if __name__ == "__main__":
    main()
