"""CPU time of the simulated world alone (`bench_sim.py`'s ten walkers in the office hallway
and ten shoppers in the store): to compare two commits' crowd step, run alternately.

Each floor runs `--ticks` ticks of 0.1 s (world.step, sonar, laser, person detection) after a
warm-up, `--repeat` times in this process, and prints the smallest user + system CPU time, of
the whole and of the crowd's step. Set PYTHONPATH to the tree under test, e.g. an old commit
unpacked with `git archive <commit> | tar -x -C /tmp/old`, and alternate the two trees:

    PYTHONPATH=/tmp/old python benchmarks/bench_world_cpu.py [--ticks 1500] [--repeat 3]
    PYTHONPATH=. python benchmarks/bench_world_cpu.py [--ticks 1500] [--repeat 3]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_sim import ten_shoppers, ten_walkers  # noqa: E402

from robots.profile import load_profile  # noqa: E402
from robots.sim.floor import load_floor  # noqa: E402
from robots.sim.scenario import parse_scenario  # noqa: E402
from robots.sim.world import World  # noqa: E402


def run_once(floor_name: str, ticks: int) -> tuple[float, float]:
    """CPU seconds of `ticks` ticks of a fresh world (after 50 ticks of warm-up), and of
    the crowd's step within them."""
    floor = load_floor(floor_name)
    people = ten_walkers() if floor_name == "office" else ten_shoppers()
    world = World(floor, load_profile("horos"), parse_scenario(people, "<bench>"), seed=1)
    world.body.set_command(0.0, 0.3)
    crowd_step, spent = world.crowd.step, [0.0]

    def timed_step(h, of_world):
        start = time.process_time()
        crowd_step(h, of_world)
        spent[0] += time.process_time() - start

    world.crowd.step = timed_step

    def tick() -> None:
        world.step(0.1)
        world.sonar_ranges()
        world.laser_scan()
        world.detect_people()

    for _ in range(50):
        tick()
    spent[0] = 0.0
    start = time.process_time()
    for _ in range(ticks):
        tick()
    return time.process_time() - start, spent[0]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ticks", type=int, default=1500)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    for floor_name in ("office", "store"):
        runs = [run_once(floor_name, args.ticks) for _ in range(args.repeat)]
        best, crowd = min(total for total, _ in runs), min(c for _, c in runs)
        print(f"{floor_name}: {best:.3f} s CPU for {args.ticks} ticks "
              f"({best / args.ticks * 1e3:.3f} ms per tick), of which the crowd's step "
              f"{crowd:.3f} s, best of {args.repeat}")


if __name__ == "__main__":
    main()
