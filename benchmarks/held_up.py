"""How long simulated people stand held up by others in the follow benchmark's runs: for each
run, each person's longest held-up spell (`SimPerson.blocked_for`: headway under a quarter of
the walk wished, robots.sim.crowd) of SPELL s or more, and how far from the robot they were
at the closest during it. People who stand frozen for half a minute facing each other are
not people who move like people (issue 23, docs/shopping.md, section *held1*).

The runs are `bench_follow.py`'s, tick by tick as `trace_follow.py` runs them (to the end or
giving up), sampled once a second.

    python benchmarks/held_up.py crowd10 crowd20 --seeds 3 [--first K] [--robot perses|horos]
"""
from __future__ import annotations

import argparse
import math
import sys
from contextlib import closing
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_follow as bf  # noqa: E402  (the benchmark's families)
from trace_follow import ticks  # noqa: E402  (the benchmark's run, tick by tick)

SPELL = 5.0         # s: a held-up spell this long is counted


def spells(family: str, seed: int, robot: str) -> dict[str, tuple[float, float]]:
    """Person id -> (their longest held-up spell of SPELL s or more, their least distance to
    the robot's centre while held up that long) over one benchmark run."""
    longest: dict[str, tuple[float, float]] = {}
    with closing(ticks(family, seed, robot)) as run:
        for tick, (skills, world, _, _) in enumerate(run):
            if tick % 10 == 0:
                _note(world, longest)
            if skills.following.state.phase == "gave_up":
                break
    return longest


def _note(world, longest: dict) -> None:
    body = world.body
    for person in world.present_people():
        if person.blocked_for < SPELL:
            continue
        spell, near = longest.get(person.plan.id, (0.0, math.inf))
        d = math.hypot(person.x - body.x, person.y - body.y)
        longest[person.plan.id] = (max(spell, person.blocked_for), min(near, d))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("families", nargs="+", choices=list(bf.FAMILIES))
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--first", type=int, default=0)
    parser.add_argument("--robot", default="perses")
    args = parser.parse_args()
    total = 0.0
    for family in args.families:
        for seed in range(args.first, args.first + args.seeds):
            found = spells(family, seed, args.robot)
            total += sum(spell for spell, _ in found.values())
            shown = ", ".join(f"{who} {spell:.1f} s ({near:.1f} m from the robot)"
                              for who, (spell, near) in sorted(found.items()))
            print(f"{family} seed {seed:2d}: {shown or 'nobody held up ' + str(SPELL) + ' s'}",
                  flush=True)
    print(f"longest held-up spells of {SPELL:.0f} s or more, summed: {total:.1f} s")


if __name__ == "__main__":
    main()
