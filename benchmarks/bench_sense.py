"""CPU time of the sensing skills' `sense` per tick, in a real `interbot run --fast`.

The whole tick (benchmarks/bench_tick.py) moves by 10-20 % from one run to the next on a
shared machine, more than a cut in one skill saves. This times only the skills' own `sense`
(thread CPU time, what they called included: the laser's read and its ray casting too), so
two trees run alternately compare by a figure that the rest of the loop does not move.

    python benchmarks/bench_sense.py [--app shopping --robot perses --scenario follow_me]
                                     [--duration 120]

Printed: ticks, then per skill the mean µs of CPU per tick and the share of the run's CPU.
Benchmarks are not a layer: this script wraps methods of the skills to time them.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import time
from collections import defaultdict

from applications.cli import main as interbot
from skills.localization import Localization
from skills.obstacles import ObstacleSensing
from skills.perception import PeoplePerception

SKILLS = (Localization, ObstacleSensing, PeoplePerception)


def timed(cls, spent: dict, calls: dict) -> None:
    """Wrap `cls.sense` to add its thread CPU time (ns) to `spent[cls.name]`."""
    sense = cls.sense

    def wrapper(self, now):
        start = time.thread_time_ns()
        try:
            return sense(self, now)
        finally:
            spent[cls.name] += time.thread_time_ns() - start
            calls[cls.name] += 1

    cls.sense = wrapper


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--app", default="shopping")
    parser.add_argument("--robot", default="perses")
    parser.add_argument("--scenario", default="follow_me")
    parser.add_argument("--duration", type=float, default=120.0, help="simulated seconds")
    args = parser.parse_args()
    spent: dict[str, int] = defaultdict(int)
    calls: dict[str, int] = defaultdict(int)
    for cls in SKILLS:
        timed(cls, spent, calls)
    cpu = time.process_time()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
        interbot(["run", args.app, "--robot", args.robot, "--scenario", args.scenario,
                  "--fast", "--quiet", "--seed", "0", "--duration", str(args.duration)])
    cpu = time.process_time() - cpu
    ticks = max(calls.values(), default=0)
    print(f"{args.app}/{args.robot}/{args.scenario} {args.duration:g} s: {ticks} ticks, "
          f"{cpu:.2f} CPU-s in the run")
    total = 0
    for cls in SKILLS:
        total += spent[cls.name]
        print(f"  {cls.name:13s} {spent[cls.name] / 1e3 / max(ticks, 1):8.1f} us/tick  "
              f"{100 * spent[cls.name] / 1e9 / cpu:5.1f} % of the run's CPU")
    print(f"  {'together':13s} {total / 1e3 / max(ticks, 1):8.1f} us/tick")


if __name__ == "__main__":
    main()
