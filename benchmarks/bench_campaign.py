"""How many episodes per minute a campaign does on this machine (issue 27), before and after
making runs cheap, measured in the same invocation, one run at a time:

- baseline: each run an `interbot run` in a process of its own (what campaigns did: imports
  and start-up every run), on benchmarks/campaigns/attract/visitors.toml (200 passers-by
  planned, whichever the run's length);
- worker: the same runs in one long-lived worker process (applications.campaign.worker);
- worker, passers-by of the run only: the same again on benchmarks/campaigns/week/visitors.toml,
  which plans only the 30 passers-by who can arrive in 600 s (the first 30 of the attract
  timetable, drawn alike) — a person planned for later never appears but is still looked at
  by the crowd every substep.

Each run is benchmarks/campaigns/attract/app (the learner choosing) for `--duration` s of robot
time (at most 600, so that all three meet the same people). Prints per set-up episodes and runs
per minute, the median wall time of a run, its ratio to the baseline, the CPU seconds per
episode (which do not depend on what else the machine is doing) and whether its episodes
(alternative, outcome, time) are exactly the baseline's.

    python benchmarks/bench_campaign.py [--runs 3] [--duration 120]

The figures depend on what else the machine is doing; say so with them.
"""
from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from dataclasses import asdict
from pathlib import Path

from applications.campaign import engine
from applications.campaign.spec import RunSpec

CAMPAIGNS = Path(__file__).resolve().parent / "campaigns"
ATTRACT = CAMPAIGNS / "attract"


def specs(runs: int, duration: float, scenario: Path) -> list[RunSpec]:
    return [RunSpec(app=str(ATTRACT / "app"), robot=None, map=None, scenario=str(scenario),
                    seed=seed, choose="learn", learner="thompson", freeze=False,
                    duration=duration) for seed in range(runs)]


def in_processes(grid: list[RunSpec], folder: Path, pythonpath) -> list[dict]:
    return [engine.run_one(asdict(spec), str(folder / f"run{n}"), pythonpath)
            for n, spec in enumerate(grid)]


def in_a_worker(grid: list[RunSpec], folder: Path, pythonpath) -> list[dict]:
    worker = engine.Worker(pythonpath)
    try:
        return [worker.run(spec, folder / f"run{n}") for n, spec in enumerate(grid)]
    finally:
        worker.close()


def measure(how, grid: list[RunSpec], folder: Path) -> dict:
    start = time.perf_counter()
    results = how(grid, folder, os.environ.get("PYTHONPATH"))
    wall = time.perf_counter() - start
    episodes = sum(len(r["episodes"]) for r in results)
    return {"episodes/min": episodes / wall * 60, "runs/min": len(grid) / wall * 60,
            "cpu s/episode": sum(r["cpu_seconds"] for r in results) / max(episodes, 1),
            "median run s": statistics.median(r["wall_seconds"] for r in results),
            "episodes": episodes, "failed": sum(r["exit_code"] != 0 for r in results),
            "outcomes": [[(e["alternative"], e["success"], e["t"]) for e in r["episodes"]]
                         for r in results]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--duration", type=float, default=120.0)
    args = parser.parse_args()
    if not 0 < args.duration <= 600:
        parser.error("--duration must be within 0 .. 600 s (the week's passers-by)")
    setups = (("process per run (baseline)", in_processes, ATTRACT / "visitors.toml"),
              ("worker", in_a_worker, ATTRACT / "visitors.toml"),
              ("worker, passers-by of the run", in_a_worker, CAMPAIGNS / "week" / "visitors.toml"))
    figures = {}
    with tempfile.TemporaryDirectory() as tmp:
        for n, (name, how, scenario) in enumerate(setups):
            figures[name] = measure(how, specs(args.runs, args.duration, scenario),
                                    Path(tmp) / str(n))
    print(f"{args.runs} runs of {args.duration:g} s robot time each, one at a time; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    base = figures[setups[0][0]]
    for name, f in figures.items():
        print(f"  {name:<30} {f['episodes/min']:6.1f} episodes/min, {f['runs/min']:5.2f} runs/min, "
              f"median run {f['median run s']:5.1f} s, {f['cpu s/episode']:.2f} CPU s/episode, "
              f"{f['episodes']} episodes, "
              f"{f['failed']} failed; x{f['episodes/min'] / base['episodes/min']:.2f} episodes/min, "
              f"x{base['median run s'] / f['median run s']:.2f} on the median run; "
              f"episodes {'the same as' if f['outcomes'] == base['outcomes'] else 'DIFFER from'} "
              f"the baseline's")


if __name__ == "__main__":
    main()
