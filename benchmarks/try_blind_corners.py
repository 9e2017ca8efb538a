"""An experiment, not a feature: `bench_follow.py`'s runs with the local controller also slowing
for blind corners, to see what it would take off the contacts and cost the follower.

Why: HOROS crowd20 seed 17 drove into a shopper's cart at aisle A5's north mouth (docs/
shopping.md, *turning1* and *fresh2*). The shopper came along the next aisle, hidden behind the
shelf unit between the two aisles; her track was born 0.7 s before the contact, when the robot,
at its top speed of 0.6 m/s, could no longer stop (0.5 m/s² at most). People slow down where
a wall beside them ends and somebody may step out from behind it.

The cap tried here: along the planned path ahead (as far as the robot needs to brake from its
top speed, and 0.5 m more), a side of the path is *walled* at a point when the map has a wall
within SIDE m of it, across the path; a side walled where the robot is now and open further on
is a corner the robot cannot see round. The robot may reach the first such point at no more
than `--speed` m/s (0.3, the profiles' `max_speed_near_people`), braking towards it at the
controller's planned deceleration. The controller is wrapped in this process only.

    python benchmarks/try_blind_corners.py FAMILY SEEDS [--robot horos] [--speed 0.3]

SEEDS is a comma-separated list. Each run prints the benchmark's own figures for that seed (the
share within ±0.3 m, contacts the robot drove into, all contacts, given up); the same seeds of
`bench_follow.py` on the committed code are the comparison. The guide's tours with the cap:

    python benchmarks/try_blind_corners.py guide [--speed 0.3] -- BENCH_GUIDE_ARGUMENTS

runs `bench_guide.py` with those arguments (e.g. `--buildings 10 --tours 5 --robot horos
--json FILE`) in this process, the controller wrapped.

Benchmarks are not a layer: this script wraps a method of the local controller.
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import bench_follow as bf  # noqa: E402

from skills.navigation import controller as ctl  # noqa: E402

SIDE = 1.0                 # m across the path: a wall this near hides what is beyond its end
OFFSETS = np.arange(0.1, SIDE + 1e-9, 0.1)      # m, the points probed across the path
BEYOND_BRAKING = 0.5       # m of path looked along beyond the braking distance from top speed


def walled_sides(controller, window: np.ndarray) -> list[np.ndarray]:
    """For each side of the path (left, right): at each sample of `window`, whether the map
    has a wall within SIDE m across the path."""
    step = np.diff(window, axis=0)
    heading = np.arctan2(step[:, 1], step[:, 0])
    heading = np.concatenate([heading, heading[-1:]])
    across_x, across_y = -np.sin(heading), np.cos(heading)          # the left normal
    resolution = controller.costmap.grid.resolution
    sides = []
    for side in (1.0, -1.0):
        px = window[:, 0:1] + side * across_x[:, None] * OFFSETS[None, :]
        py = window[:, 1:2] + side * across_y[:, None] * OFFSETS[None, :]
        sides.append((controller._map_clearance(px, py) < resolution).any(axis=1))
    return sides


def blind_corner_cap(controller, path, arc, stretch, speed: float) -> float:
    """The speed now that reaches the first corner ahead the robot cannot see round at
    `speed`, braking at the controller's planned deceleration; inf without one."""
    p, limits = controller.params, controller.limits
    braking = limits.max_speed ** 2 / (2 * p.brake * limits.max_accel)
    ahead = stretch or ctl._PathAhead(controller, path, arc)
    window, along = ahead.window(braking + BEYOND_BRAKING)
    if len(window) < 3:
        return math.inf
    cap = math.inf
    for walled in walled_sides(controller, window):
        opens = np.flatnonzero(~walled)
        if walled[0] and len(opens):
            room = float(along[opens[0]])
            cap = min(cap, math.sqrt(speed ** 2 + 2 * p.brake * limits.max_accel * room))
    return cap


def slow_at_blind_corners(speed: float) -> None:
    """Wrap the controller's speed cap (in this process) with `blind_corner_cap`."""
    plain = ctl.LocalController._speed_cap

    def capped(self, x, y, th, v0, path, crowd, max_speed, arc=None, stretch=None):
        cap, why = plain(self, x, y, th, v0, path, crowd, max_speed, arc, stretch)
        if len(path) >= 2:
            corner = blind_corner_cap(self, path, arc, stretch, speed)
            if corner < cap:
                return corner, "blind corner"
        return cap, why

    ctl.LocalController._speed_cap = capped


def guide(arguments: list[str]) -> None:
    """`bench_guide.py` with `arguments`, the controller wrapped (`guide [--speed S] -- ...`)."""
    speed = 0.3
    if arguments[:1] == ["--speed"]:
        speed, arguments = float(arguments[1]), arguments[2:]
    if arguments[:1] == ["--"]:
        arguments = arguments[1:]
    import bench_guide
    slow_at_blind_corners(speed)
    sys.argv = ["bench_guide.py", *arguments]
    bench_guide.main()


def main() -> None:
    if sys.argv[1:2] == ["guide"]:
        guide(sys.argv[2:])
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("family", choices=list(bf.FAMILIES))
    parser.add_argument("seeds", help="comma-separated, e.g. 12,13,14")
    parser.add_argument("--robot", default="perses")
    parser.add_argument("--speed", type=float, default=0.3,
                        help="m/s at a blind corner (default 0.3)")
    options = parser.parse_args()
    slow_at_blind_corners(options.speed)
    for seed in (int(s) for s in options.seeds.split(",")):
        with tempfile.TemporaryDirectory() as folder:
            r = bf.run(seed, options.robot, Path(folder), None, options.family)
        share = 100.0 * r.in_tight_band / max(r.ticks, 1)
        print(f"{options.family} seed {seed:2d} ({options.robot}, blind corners at "
              f"{options.speed} m/s): ±0.3 m {share:5.1f}%, robot drove in {r.drove_into}, "
              f"collisions {r.collisions}, {'GAVE UP' if r.gave_up else 'kept her'}",
              flush=True)


if __name__ == "__main__":
    main()
