"""How many runs per minute a campaign does on this machine (issue 27).

Runs the same small grid twice, measured in the same invocation: one run at a time (the
baseline: what running the seeds one after another does) and `--workers` at once (local
processes, the default engine). Each run is an `interbot run` of benchmarks/campaigns/attract (visitors
with hidden propensities, the learner choosing) for `--duration` s of robot time. Prints per
set-up runs per minute, the median wall time of a run, robot seconds per wall second, and the
ratio of the two.

    python benchmarks/bench_campaign.py [--runs 4] [--duration 120] [--workers 2]

The figures depend on what else the machine is doing; say so with them.
"""
from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

from applications.campaign import engine
from applications.campaign.spec import RunSpec

ATTRACT = Path(__file__).resolve().parents[1] / "campaigns" / "attract"


def measure(runs: int, duration: float, workers: int, folder: Path) -> dict:
    grid = [(RunSpec(app=str(ATTRACT / "app"), robot=None, map=None,
                     scenario=str(ATTRACT / "visitors.toml"), seed=seed, choose="learn",
                     learner="thompson", freeze=False, duration=duration), folder / f"run{seed}")
            for seed in range(runs)]
    start = time.perf_counter()
    results = [result for _, result in engine.local(grid, workers, os.environ.get("PYTHONPATH"))]
    wall = time.perf_counter() - start
    failed = sum(r["exit_code"] != 0 for r in results)
    return {"runs/min": runs / wall * 60, "median run s": statistics.median(
        r["wall_seconds"] for r in results), "robot s per wall s": runs * duration / wall,
        "episodes": sum(len(r["episodes"]) for r in results), "failed": failed, "wall": wall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=4)
    parser.add_argument("--duration", type=float, default=120.0)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        one = measure(args.runs, args.duration, 1, Path(tmp) / "one")
        many = measure(args.runs, args.duration, args.workers, Path(tmp) / "many")
    print(f"{args.runs} runs of {args.duration:g} s robot time, load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    for name, figures in (("1 at a time (baseline)", one), (f"{args.workers} at once", many)):
        print(f"  {name:<24} " + ", ".join(f"{k} {v:.1f}" if isinstance(v, float) else f"{k} {v}"
                                          for k, v in figures.items()))
    print(f"  ratio {args.workers} at once / baseline: "
          f"{many['runs/min'] / one['runs/min']:.2f} x runs per minute")


if __name__ == "__main__":
    main()
