"""Micro-benchmark of the simulated world: the cost of one 0.1 s tick of the L0 simulation
(world.step + sonar + laser + person detection) with 10 people walking the office hallway, or
10 shoppers (half with carts) walking between random shelves of the store.

Prints median and p99 in microseconds for each part and for the whole tick, and three ratios
measured in the same run: 10 people against an empty world, the world with its evaluation
measures against the same world without them, and the vectorised ray caster against a plain
Python loop over rays and walls (the baseline it replaces).

    python benchmarks/bench_sim.py [--ticks N] [--robot horos|perses] [--floor office|store]
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np

from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.raycast import cast_rays
from robots.sim.scenario import parse_scenario
from robots.sim.world import World


def ten_walkers() -> dict:
    """Ten people pacing the hallway back and forth, at different speeds and offsets."""
    people = []
    for i in range(10):
        y = -0.2 + 0.1 * i
        people.append({"id": f"p{i}", "appear": 0.0, "at": [-9.0 + 1.8 * i, y],
                       "speed": 0.6 + 0.08 * i,
                       "steps": [{"walk": [[9.0, y], [-9.0, y]] * 20}]})
    return {"scenario": {"name": "bench", "duration": 600.0}, "person": people}


def ten_shoppers() -> dict:
    """Ten shoppers in the store, every second one with a cart, each visiting 50 random
    shelves (enough for any run) and dwelling 1..4 s at each."""
    people = [{"id": f"s{i}", "appear": 0.0, "at": "street", "speed": 0.7 + 0.06 * i,
               "cart": i % 2 == 0,
               "steps": [{"shop": "shelf_", "count": 50, "dwell": [1.0, 4.0]}]}
              for i in range(10)]
    return {"scenario": {"name": "bench", "duration": 600.0, "floor": "store"},
            "person": people}


def time_tick(world: World, ticks: int) -> dict[str, np.ndarray]:
    parts = {"step": [], "sonar": [], "laser": [], "detect": [], "tick": []}
    world.body.set_command(0.0, 0.3)
    clock = time.perf_counter
    for _ in range(ticks):
        t0 = clock()
        world.step(0.1)
        t1 = clock()
        world.sonar_ranges()
        t2 = clock()
        world.laser_scan()
        t3 = clock()
        world.detect_people()
        t4 = clock()
        for name, value in (("step", t1 - t0), ("sonar", t2 - t1), ("laser", t3 - t2),
                            ("detect", t4 - t3), ("tick", t4 - t0)):
            parts[name].append(value * 1e6)
    return {name: np.array(values) for name, values in parts.items()}


def python_loop_laser(origin, angles, segments, max_range) -> list[float]:
    """The baseline: one ray at a time, one wall at a time."""
    out = []
    for angle in angles:
        dx, dy = math.cos(angle), math.sin(angle)
        best = math.inf
        for x1, y1, x2, y2 in segments:
            ex, ey = x2 - x1, y2 - y1
            denom = dx * ey - dy * ex
            if denom == 0:
                continue
            qx, qy = x1 - origin[0], y1 - origin[1]
            t = (qx * ey - qy * ex) / denom
            s = (qx * dy - qy * dx) / denom
            if t >= 0 and 0 <= s <= 1:
                best = min(best, t)
        out.append(best if best <= max_range else math.inf)
    return out


def median_us(func, repeat: int) -> float:
    samples = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        func()
        samples.append((time.perf_counter() - t0) * 1e6)
    return float(np.median(samples))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ticks", type=int, default=3000)
    parser.add_argument("--robot", default="horos")
    parser.add_argument("--floor", default="office", choices=("office", "store"))
    args = parser.parse_args()
    profile = load_profile(args.robot)
    floor = load_floor(args.floor)
    people = ten_walkers() if args.floor == "office" else ten_shoppers()

    crowd = World(floor, profile, parse_scenario(people, "<bench>"), seed=1)
    empty = World(floor, profile, None, seed=1)
    unmeasured = World(floor, profile, parse_scenario(people, "<bench>"), seed=1)
    unmeasured.measures.update = lambda world, dt, walls=None: None
    time_tick(crowd, 200)                                  # warm up
    time_tick(empty, 200)
    time_tick(unmeasured, 200)
    crowded = time_tick(crowd, args.ticks)
    alone = time_tick(empty, args.ticks)
    bare = time_tick(unmeasured, args.ticks)

    print(f"simulated world, robot {args.robot}, floor {args.floor} "
          f"({len(floor.segments)} walls), {args.ticks} ticks of 0.1 s")
    print(f"{'part':8s} {'median us':>10s} {'p99 us':>10s}   (10 people)")
    for name, values in crowded.items():
        print(f"{name:8s} {np.median(values):10.1f} {np.percentile(values, 99):10.1f}")
    ratio = np.median(crowded["tick"]) / np.median(alone["tick"])
    print(f"empty world tick median {np.median(alone['tick']):.1f} us; "
          f"10 people cost x{ratio:.2f} of it")
    measured = np.median(crowded["step"]) / np.median(bare["step"])
    print(f"world.step with measures / without: x{measured:.2f} "
          f"(median {np.median(bare['step']):.1f} us without)")

    laser = profile.laser
    angles = laser.heading + np.linspace(-laser.fov / 2, laser.fov / 2, laser.beams)
    origin = np.zeros((laser.beams, 2))
    fast = median_us(lambda: cast_rays(origin, angles, floor.segments, None, laser.max_range), 300)
    slow = median_us(lambda: python_loop_laser((0.0, 0.0), angles, floor.segments,
                                               laser.max_range), 30)
    print(f"laser ray cast ({laser.beams} rays x {len(floor.segments)} walls): vectorised "
          f"{fast:.1f} us, Python loop baseline {slow:.1f} us, speed-up x{slow / fast:.0f}")


if __name__ == "__main__":
    main()
