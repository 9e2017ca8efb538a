"""How often the tracker splits a standing person in two: the draw of the property test
`test_people_standing_apart_get_one_track_each_whatever_the_detection_order`, over many seeds.

n people (1..8) stand 0.9 m apart along x at random y in ±3 m, seen for 15 frames at 10 Hz
with sigma 0.05 m noise in a shuffled order; a run fails when, from the third frame on, the
tracks are not one per person, each on the same person throughout (docs/tracking.md,
`leftover_reach`).

    python benchmarks/standing_apart.py [--first 0] [--seeds 3000]
"""
from __future__ import annotations

import argparse

import numpy as np

from skills.people import PeopleTracker

NOISE = np.eye(2) * 0.05 ** 2


def splits(n: int, seed: int) -> bool:
    """True when the run of n people drawn from `seed` does not keep one track per person."""
    rng = np.random.default_rng(seed)
    people = np.column_stack((np.arange(n) * 0.9, rng.uniform(-3, 3, n)))
    tracker = PeopleTracker()
    owners = None
    for k in range(15):
        points = people + rng.normal(0, 0.05, people.shape)
        order = rng.permutation(n)
        tracks = tracker.update(k * 0.1, [(x, y, NOISE) for x, y in points[order]])
        if k < 2:
            continue
        owner = {t.id: int(np.argmin(np.hypot(*(people - (t.x, t.y)).T))) for t in tracks}
        owners = owners or owner
        if owner != owners:
            return True
    return len(owners) != n or sorted(owners.values()) != list(range(n))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--first", type=int, default=0)
    parser.add_argument("--seeds", type=int, default=3000)
    args = parser.parse_args()
    seeds = range(args.first, args.first + args.seeds)
    failed = [(n, seed) for n in range(1, 9) for seed in seeds if splits(n, seed)]
    print(f"seeds {seeds.start}..{seeds.stop - 1}, 1..8 people: {len(failed)} of "
          f"{8 * len(seeds)} runs split a person or swapped two; (people, seed): {failed}")


if __name__ == "__main__":
    main()
