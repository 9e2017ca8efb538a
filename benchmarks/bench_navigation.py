"""Benchmark of planning and driving on the office floor.

1. Global planner: time per path over many random start/goal pairs on the office map (median,
   p99; target <= 100 ms), against a plain Python A* on the same graph measured in the same run
   (the baseline the compiled search replaces), on a subset of the pairs.
2. Local controller: cost per tick with 10 people around the robot (median, p99; must be well
   inside the 100 ms tick), and the whole navigation tick (sense + act of every skill).
3. Driving in the simulated office: time to goal divided by the time at full speed along the
   shortest path (target <= 1.6), over a set of start/goal places; minimum clearance between
   the body and the walls.
4. Driving through the hallway with the 10 people of (2) (they pace, then stand along it):
   arrivals, time, nearest approach to a person (centre to centre) and ticks in contact.

    python benchmarks/bench_navigation.py [--pairs N] [--robot horos|perses]

Prints the load average beside the figures: the machine is shared.
"""
from __future__ import annotations

import argparse
import heapq
import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from robots.sim.raycast import point_segment_distances
from skills.navigation.controller import LocalController, Person
from skills.navigation.costmap import cost_map
from skills.navigation.gridmap import load_map
from skills.navigation.planner import COST_WEIGHT, GlobalPlanner
from skills.skillset import open_skills

DRIVES = [("robot_home", "room_n2"), ("robot_home", "room_s4"), ("room_n1", "room_s3"),
          ("room_s1", "room_n4"), ("hall_west", "room_n3"), ("room_n4", "hall_west"),
          ("room_s2", "room_n2"), ("hall_east", "room_s1")]


def percentiles(values) -> str:
    values = np.asarray(values, dtype=float)
    return f"median {np.median(values):8.2f}  p99 {np.percentile(values, 99):8.2f}"


# -- 1. the global planner -------------------------------------------------------------------

def random_pairs(costmap, count: int, rng) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """Free cells inside the building (the map's border outside the outer walls is free but
    closed off), at least 3 m apart."""
    grid = costmap.grid
    xs, ys = grid.to_world(*np.indices(grid.shape))
    inside = (np.abs(xs) < 10.0) & (np.abs(ys) < 5.2)
    free = np.argwhere(~costmap.lethal & inside)
    pairs = []
    while len(pairs) < count:
        a, b = free[rng.integers(len(free), size=2)]
        ax, ay = grid.to_world(a[0], a[1])
        bx, by = grid.to_world(b[0], b[1])
        if math.hypot(bx - ax, by - ay) > 3.0:
            pairs.append(((float(ax), float(ay)), (float(bx), float(by))))
    return pairs


def python_astar(costmap, start, goal) -> float:
    """The baseline: A* with an octile heuristic, one cell at a time in Python."""
    grid = costmap.grid
    lethal, cost, res = costmap.lethal, costmap.cost, grid.resolution
    rows, cols = lethal.shape
    s = tuple(int(v) for v in grid.to_cells(*start))
    g = tuple(int(v) for v in grid.to_cells(*goal))
    steps = [(dr, dc, res * math.hypot(dr, dc)) for dr in (-1, 0, 1) for dc in (-1, 0, 1)
             if dr or dc]
    best = {s: 0.0}
    queue = [(0.0, 0.0, s)]
    while queue:
        _, d, cell = heapq.heappop(queue)
        if cell == g:
            return d
        if d > best.get(cell, math.inf):
            continue
        r, c = cell
        for dr, dc, length in steps:
            nr, nc = r + dr, c + dc
            if not (0 <= nr < rows and 0 <= nc < cols) or lethal[nr, nc]:
                continue
            nd = d + length * (1.0 + COST_WEIGHT * 0.5 * (cost[r, c] + cost[nr, nc]))
            if nd < best.get((nr, nc), math.inf):
                best[(nr, nc)] = nd
                h = res * (max(abs(g[0] - nr), abs(g[1] - nc))
                           + (math.sqrt(2) - 1) * min(abs(g[0] - nr), abs(g[1] - nc)))
                heapq.heappush(queue, (nd + h, nd, (nr, nc)))
    return math.inf


def bench_planner(pairs_count: int, radius: float) -> None:
    t0 = time.perf_counter()
    grid = load_map("office")
    t1 = time.perf_counter()
    costmap = cost_map(grid, radius)
    planner = GlobalPlanner(costmap)
    planner.plan(grid.place("robot_home")[:2], grid.place("room_n1")[:2])   # builds the graph
    t2 = time.perf_counter()
    print(f"office map {grid.shape[1]}x{grid.shape[0]} cells of {grid.resolution} m: "
          f"drawn in {1e3 * (t1 - t0):.0f} ms; cost map + graph (once per map) "
          f"{1e3 * (t2 - t1):.0f} ms")
    rng = np.random.default_rng(7)
    pairs = random_pairs(costmap, pairs_count, rng)
    times, found = [], 0
    for start, goal in pairs:
        a = time.perf_counter()
        plan = planner.plan(start, goal)
        times.append(1e3 * (time.perf_counter() - a))
        found += plan.found
    print(f"global plan, {len(pairs)} random pairs (>3 m apart), ms: {percentiles(times)}   "
          f"found {found}/{len(pairs)}   (target <= 100 ms)")
    subset = pairs[: max(3, len(pairs) // 20)]
    ours, base = [], []
    for start, goal in subset:
        a = time.perf_counter()
        planner.plan(start, goal)
        b = time.perf_counter()
        python_astar(costmap, start, goal)
        c = time.perf_counter()
        ours.append(b - a)
        base.append(c - b)
    print(f"  baseline Python A* on {len(subset)} of the pairs: median "
          f"{1e3 * np.median(base):.1f} ms; compiled search {1e3 * np.median(ours):.1f} ms; "
          f"ratio {np.median(base) / np.median(ours):.1f}x")


# -- 2. the local controller with 10 people ------------------------------------------------

def ten_people_scenario(folder: Path) -> Path:
    lines = ['[scenario]', 'name = "ten"', 'duration = 600.0', 'robot = "hall_east"']
    for i in range(10):
        y = -0.9 + 0.2 * i
        x0 = -8.0 + 1.5 * i
        lines += ['[[person]]', f'id = "p{i}"', 'appear = 0.0', f'at = [{x0}, {y:.2f}]',
                  f'speed = {0.5 + 0.07 * i:.2f}',
                  f'steps = [ {{ walk = [[{x0 + 4.0}, {y:.2f}], [{x0}, {y:.2f}]] }}, '
                  f'{{ walk = [[{x0 + 4.0}, {y:.2f}], [{x0}, {y:.2f}]] }}, {{ pause = 600.0 }} ]']
    path = folder / "ten.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def bench_controller(robot: str, ticks: int, folder: Path) -> None:
    skills = open_skills(robot, fast=True, scenario=ten_people_scenario(folder))
    clock, world = skills.hardware.clock, skills.hardware.simulation.world
    nav = skills.navigation
    try:
        for _ in range(10):
            skills.sense(); skills.act(); clock.advance(0.1)
        nav.go_to("hall_west", skills.now(), speed=0.3)
        controller: LocalController = nav.controller
        step_ms, tick_ms = [], []
        previous = {p.id: (p.x, p.y) for p in world.present_people()}
        for _ in range(ticks):
            a = time.perf_counter()
            skills.sense(); skills.act()
            tick_ms.append(1e3 * (time.perf_counter() - a))
            clock.advance(0.1)
            state = skills.localization.state
            people = []
            for p in world.present_people():
                px, py = previous.get(p.id, (p.x, p.y))
                people.append(Person(p.x, p.y, (p.x - px) / 0.1, (p.y - py) / 0.1))
                previous[p.id] = (p.x, p.y)
            if nav.plan is None:
                continue
            rest = nav._rest_of_path(state.x, state.y)
            a = time.perf_counter()
            controller.step((state.x, state.y, state.th), (state.v, state.w), rest,
                            points=nav.points, people=people)
            step_ms.append(1e3 * (time.perf_counter() - a))
        print(f"local controller, 10 people + {len(nav.points)} readings, ms per tick: "
              f"{percentiles(step_ms)}   (tick is 100 ms)")
        print(f"  whole tick of every skill with the simulated world stepped (sense + act), "
              f"ms: {percentiles(tick_ms)}")
    finally:
        skills.close()


# -- 3. driving ----------------------------------------------------------------------------

def bench_drives(robot: str, folder: Path) -> None:
    grid = load_map("office")
    shortest = GlobalPlanner(cost_map(grid, 0.26), cost_weight=0.0)
    ratios, clearances = [], []
    for start, goal in DRIVES:
        scenario = folder / f"{start}.toml"
        scenario.write_text(f'[scenario]\nname = "{start}"\nduration = 120.0\n'
                            f'robot = "{start}"\n')
        skills = open_skills(robot, fast=True, scenario=scenario)
        clock, world = skills.hardware.clock, skills.hardware.simulation.world
        try:
            for _ in range(5):
                skills.sense(); skills.act(); clock.advance(0.1)
            t0 = skills.now()
            skills.navigation.go_to(goal, t0)
            gap = math.inf
            for _ in range(1200):
                skills.sense(); skills.act(); clock.advance(0.1)
                body = world.body
                gap = min(gap, float(point_segment_distances(body.x, body.y, world._walls).min())
                          - body.radius)
                if not skills.navigation.status.running:
                    break
            took = skills.now() - t0
            status = skills.navigation.status
        finally:
            skills.close()
        best = shortest.plan(grid.place(start)[:2], grid.place(goal)[:2]).length
        ideal = best / skills.profile.limits.max_speed
        ratio = took / ideal
        ratios.append(ratio)
        clearances.append(gap)
        print(f"  {start:>10} -> {goal:<9} {status.status.value:9} {took:5.1f} s "
              f"(full speed on the shortest path {ideal:4.1f} s) ratio {ratio:4.2f}  "
              f"min wall clearance {gap:.3f} m")
    print(f"drive time / full-speed shortest time over {len(DRIVES)} drives: median "
          f"{np.median(ratios):.2f}, max {max(ratios):.2f} (target <= 1.6); min wall clearance "
          f"{min(clearances):.3f} m")


def bench_crowd(robot: str, seeds: int, folder: Path) -> None:
    scenario = ten_people_scenario(folder)
    arrived, nearest, contacts, times = 0, math.inf, 0, []
    for seed in range(seeds):
        skills = open_skills(robot, fast=True, scenario=scenario, seed=seed)
        clock, world = skills.hardware.clock, skills.hardware.simulation.world
        try:
            for _ in range(10):
                skills.sense(); skills.act(); clock.advance(0.1)
            t0 = skills.now()
            skills.navigation.go_to("hall_west", t0)
            for _ in range(2400):
                skills.sense(); skills.act(); clock.advance(0.1)
                body = world.body
                for person in world.present_people():
                    nearest = min(nearest, math.hypot(person.x - body.x, person.y - body.y))
                contacts += body.stalled
                if not skills.navigation.status.running:
                    break
            arrived += skills.navigation.status.succeeded
            times.append(skills.now() - t0)
        finally:
            skills.close()
    print(f"hall_east -> hall_west through 10 people, {seeds} seeds: arrived {arrived}/{seeds}, "
          f"median {np.median(times):.0f} s, nearest person {nearest:.2f} m centre to centre, "
          f"ticks in contact {contacts}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=200)
    parser.add_argument("--ticks", type=int, default=300)
    parser.add_argument("--robot", default="horos")
    parser.add_argument("--crowd-seeds", type=int, default=5)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        bench_planner(args.pairs, 0.26)
        bench_controller(args.robot, args.ticks, folder)
        print(f"drives on the office floor ({args.robot}):")
        bench_drives(args.robot, folder)
        bench_crowd(args.robot, args.crowd_seeds, folder)
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
