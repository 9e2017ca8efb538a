"""Benchmark of the office guide: many seeded tours of a visitor who follows the robot.

Each tour (seed i) starts with the robot at robot_home and a visitor standing in front of it;
GuidePerson leads them to a room drawn at random (the eight rooms of the office), at the
behavior's default pace (the profile's max_speed). The visitor follows at a distance and walking speed drawn
per tour; up to two other people come in at an end of the hallway and walk along one side
of it and back (the simulated
people do not avoid the robot: one may walk into it while it stands). Per tour, from the simulator's ground truth
(`world.measures`, robots/sim/measures.py) and the robot's own state:

- success: GuidePerson arrived, with the visitor within 2.5 m (centre to centre) at that moment;
- collisions (contacts) with people and walls, split into the robot driving into someone and
  someone walking into the standing robot; the minimum gap to any person;
- personal-space intrusions (gap < 0.45 m while closing in), by the robot and by people;
- the largest speed with someone within 1 m;
- time from leading off to arrival divided by the time at full speed (the profile's max_speed)
  along the shortest path (no wall margin);
- localization error: estimate against the ground truth, every tick;
- planner time: every global plan made during the tours.

Then the cost of the robot's whole tick (sense + act: every skill, the behavior tree, the
simulated world stepped) while guiding with 10 people around.

    python benchmarks/bench_guide.py [--tours N] [--robot horos|perses] [--ticks N]
    python benchmarks/bench_guide.py --buildings B [--tours N] [--robot R] [--first-building F]
        [--first-tour T] [--json FILE]
    python benchmarks/bench_guide.py --pool FILE [FILE ...]

With `--buildings B` the tours run in B generated office buildings (`benchmarks/buildings.py`,
seeds 0 .. B-1; map_server maps simulated from their cells), N tours each: the robot at
`robot_home`, the visitor standing 1 m along the hallway from it (on the side away from the
room), a room drawn from the
building's `room_NN` places, no other people; reported per building and pooled. A campaign
may be split over processes: `--first-building F` runs buildings F .. F+B-1, `--first-tour T`
tours (seeds) T .. T+N-1, `--json FILE` writes one line per tour, and `--pool FILE ...`
reports those lines together (per building, pooled, the worst building).

Prints the load average beside the figures: the machine is shared.
"""
from __future__ import annotations

import argparse
import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from behaviors.robot import open_robot
from skills.navigation.costmap import cost_map
from skills.navigation.gridmap import load_map
from skills.navigation.planner import GlobalPlanner

ROOMS = [f"room_{side}{n}" for side in "ns" for n in range(1, 5)]
LEAD_OFF = 0.3             # m: the first metres of a tour count as leading off
WITH_USER = 2.5            # m: the visitor counts as arrived with the robot within this
TOUR_LIMIT = 150.0         # s of robot time per tour


def building_tour(folder: Path, map_path: Path, rooms: list[str], shortest, seed: int
                  ) -> tuple[Path, str]:
    """The scenario of tour `seed` in a generated building: the visitor only, standing 1 m
    from the robot along the hallway on the side away from the room (a hallway may be 1 m
    wide, and the simulated visitor does not step aside)."""
    rng = np.random.default_rng(seed)
    room = str(rng.choice(rooms))
    follow = rng.uniform(0.9, 1.5)
    speed = rng.uniform(0.9, 1.3)
    grid = shortest.costmap.grid
    home = grid.places["robot_home"]
    way = shortest.plan(home[:2], grid.places[room][:2]).waypoints
    east = way[min(1, len(way) - 1)][0] >= home[0]
    x, y = home[0] + (-1.0 if east else 1.0), home[1] + 0.3
    lines = ['[scenario]', f'name = "tour{seed}"', f'duration = {TOUR_LIMIT}',
             'robot = "robot_home"', f'map = "{map_path}"',
             '[[person]]', 'id = "visitor"', f'at = [{x:.2f}, {y:.2f}]', f'speed = {speed:.2f}',
             f'steps = [ {{ follow = {follow:.2f}, after_call = true, goal = "{room}" }} ]']
    path = folder / f"{map_path.stem}_tour{seed}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path, room


def tour_scenario(folder: Path, seed: int) -> tuple[Path, str]:
    """The scenario of tour `seed` and the room it goes to."""
    rng = np.random.default_rng(seed)
    room = str(rng.choice(ROOMS))
    follow = rng.uniform(0.9, 1.5)
    speed = rng.uniform(0.9, 1.3)
    lines = ['[scenario]', f'name = "tour{seed}"', f'duration = {TOUR_LIMIT}',
             'robot = "robot_home"',
             '[[person]]', 'id = "visitor"', f'at = [{rng.uniform(-0.3, 0.3):.2f}, '
             f'{rng.uniform(0.3, 0.5):.2f}]', f'speed = {speed:.2f}',
             f'steps = [ {{ follow = {follow:.2f}, after_call = true, goal = "{room}" }} ]']
    for k in range(int(rng.integers(0, 3))):
        y = rng.choice([-1.0, 1.0]) * rng.uniform(0.7, 0.9)     # people keep to a side
        x0 = rng.choice([-1.0, 1.0]) * 9.0                    # they come in at an end
        x1 = -x0 * rng.uniform(0.3, 1.0)
        lines += ['[[person]]', f'id = "walker{k}"', f'appear = {rng.uniform(0, 10):.1f}',
                  f'at = [{x0:.2f}, {y:.2f}]', f'speed = {rng.uniform(0.6, 1.2):.2f}',
                  f'steps = [ {{ walk = [[{x1:.2f}, {y:.2f}], [{x0:.2f}, {y:.2f}]] }}, '
                  f'{{ walk = [[{x1:.2f}, {y:.2f}]] }} ]']
    path = folder / f"tour{seed}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path, room


class Timed:
    """Wraps a planner's `plan` to collect its wall time per call (ms)."""

    def __init__(self, planner, into: list) -> None:
        self.planner, self.into = planner, into

    def __call__(self, *args, **kwargs):
        a = time.perf_counter()
        try:
            return self.planner(*args, **kwargs)
        finally:
            self.into.append(1e3 * (time.perf_counter() - a))


def run_tour(robot_name: str, folder: Path, seed: int, shortest, plan_ms: list,
             scenario: tuple[Path, str] | None = None) -> dict:
    path, room = scenario or tour_scenario(folder, seed)
    robot = open_robot(robot_name, fast=True, scenario=path, seed=seed)
    skills = robot.skills
    world = skills.hardware.simulation.world
    nav = skills.navigation
    nav.planner.plan = Timed(nav.planner.plan, plan_ms)
    errors, headings, outcome, duration, with_user = [], [], "timeout", None, False
    reason = ""
    try:
        for _ in range(10):
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        robot.activate("GuidePerson", {"place": room})
        split: dict[str, list[float]] = {}
        driven, last = 0.0, (world.body.x, world.body.y)
        for _ in range(int(TOUR_LIMIT / 0.1)):
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
            est, body = skills.localization.state, world.body
            step = math.hypot(body.x - last[0], body.y - last[1])
            last, driven = (body.x, body.y), driven + step
            if skills.guide.active:
                cause = split.setdefault(time_cause(skills, driven), [0.0, 0.0])
                cause[0] += 0.1
                cause[1] += step
            errors.append(math.hypot(est.x - body.x, est.y - body.y))
            headings.append(abs(math.atan2(math.sin(est.th - body.th), math.cos(est.th - body.th))))
            for event in robot.events():
                if event["kind"] == "guide":
                    outcome, duration = event["outcome"], event["duration"]
                    reason = event.get("reason", "")
                    visitor = next(p for p in world.people if p.id == "visitor")
                    with_user = math.hypot(visitor.x - body.x, visitor.y - body.y) <= WITH_USER
            if outcome != "timeout":
                break
        measures = world.measures.summary()
        measures["contacts_driving"] = sum(1 for c in world.measures.contacts
                                           if c.kind == "person" and c.robot_moving)
        measures["contacts"] = list(world.measures.contacts)
        measures["intrusions"] = list(world.measures.intrusions)
        limits = skills.profile.limits
    finally:
        robot.close()
    length = shortest.plan(shortest.costmap.grid.place("robot_home")[:2],
                           shortest.costmap.grid.place(room)[:2]).length
    return {"seed": seed, "room": room, "outcome": outcome, "reason": reason,
            "with_user": with_user,
            "success": outcome == "arrived" and with_user, "duration": duration,
            "ratio": None if duration is None else duration / (length / limits.max_speed),
            "loc_errors": errors, "heading_errors": headings,
            "time_split": {k: (round(s, 1), round(m, 2)) for k, (s, m) in split.items()},
            "max_speed": limits.max_speed, "shortest": length, **measures}


def time_cause(skills, driven: float) -> str:
    """What holds the guide's robot below full speed this tick (for the time split): the
    guide waiting, navigation blocked or turning on the goal, the first metres, else the
    controller's speed cap (people near, a narrow passage, the goal ahead, turning on the
    spot) or nothing (accelerating, curves, full speed)."""
    nav = skills.navigation.state
    if skills.guide.state.phase == "waiting":
        return "waiting for the visitor"
    if nav.phase == "blocked":
        return "blocked"
    if nav.phase in ("turning", "arrived"):
        return "turning on the goal"
    if driven < LEAD_OFF:
        return f"leading off (first {LEAD_OFF} m)"
    cap = nav.reason.split(";")[0]
    for known in ("people near", "narrow passage", "goal ahead", "turning", "obstruction",
                  "requested speed", "blind corner"):     # the last: try_blind_corners.py
        if cap.startswith(known):
            return known
    return "no cap (accelerating, curves, full speed)"


def ten_people(folder: Path) -> Path:
    """The visitor following to room_s4 and nine people pacing the hallway around the robot."""
    lines = ['[scenario]', 'name = "ten"', 'duration = 120.0', 'robot = "robot_home"',
             '[[person]]', 'id = "visitor"', 'at = [0.0, 0.4]',
             'steps = [ { follow = 1.2, after_call = true, goal = "room_s4" } ]']
    for i in range(9):
        y = -0.8 + 0.2 * i
        x0 = -8.0 + 1.8 * i
        lines += ['[[person]]', f'id = "p{i}"', f'at = [{x0:.1f}, {y:.2f}]',
                  f'speed = {0.5 + 0.07 * i:.2f}',
                  f'steps = [ {{ walk = [[{x0 + 4.0:.1f}, {y:.2f}], [{x0:.1f}, {y:.2f}]] }}, '
                  f'{{ walk = [[{x0 + 4.0:.1f}, {y:.2f}], [{x0:.1f}, {y:.2f}]] }}, '
                  f'{{ pause = 600.0 }} ]']
    path = folder / "ten.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def bench_tick(robot_name: str, folder: Path, ticks: int) -> None:
    robot = open_robot(robot_name, fast=True, scenario=ten_people(folder), seed=0)
    try:
        for _ in range(10):
            robot.sense(); robot.act(); robot.wait_until(robot.now() + 0.1)
        robot.activate("GuidePerson", {"place": "room_s4"})
        tick_ms = []
        for _ in range(ticks):
            a = time.perf_counter()
            robot.sense(); robot.act()
            tick_ms.append(1e3 * (time.perf_counter() - a))
            robot.wait_until(robot.now() + 0.1)
        people = len(robot.skills.hardware.simulation.world.present_people())
    finally:
        robot.close()
    print(f"whole tick while guiding with {people} people in the world (sense + act: skills, "
          f"behavior tree, simulated world stepped), {ticks} ticks: median "
          f"{np.median(tick_ms):.1f} ms, p99 {np.percentile(tick_ms, 99):.1f} ms "
          f"(the tick is 100 ms)")


def report(results: list[dict], plan_ms: list) -> None:
    n = len(results)
    ok = [r for r in results if r["success"]]
    outcomes: dict[str, int] = {}
    for r in results:
        key = r["outcome"] + ("" if r["with_user"] or r["outcome"] != "arrived"
                              else " (visitor not within 2.5 m)")
        outcomes[key] = outcomes.get(key, 0) + 1
    ratios = [r["ratio"] for r in ok]
    errors = np.concatenate([r["loc_errors"] for r in results])
    headings = np.degrees(np.concatenate([r["heading_errors"] for r in results]))
    print(f"tours: {n}; success {len(ok)}/{n} = {100 * len(ok) / n:.1f} % (target >= 95 %); "
          f"outcomes {outcomes}")
    failed = [(r["seed"], r["room"], r["outcome"], r["reason"][:90]) for r in results
              if not r["success"]]
    if failed:
        print(f"  not successful (seed, room, outcome, reason): {failed}")
    driving = sum(r["contacts_driving"] for r in results)
    print(f"contacts: with people {sum(r['contacts_person'] for r in results)} (the robot "
          f"driving: {driving}; people walking into the standing robot: "
          f"{sum(r['contacts_person'] for r in results) - driving}), with walls "
          f"{sum(r['contacts_wall'] for r in results)} (target 0)")
    print(f"min gap to any person {min(r['min_clearance_to_people'] for r in results):.3f} m; "
          f"min gap to a wall {min(r['min_wall_clearance'] for r in results):.3f} m")
    contacts = [(r["seed"], c.who, round(c.t, 1), "driving" if c.robot_moving else "standing")
                for r in results for c in r["contacts"] if c.kind == "person"]
    if contacts:
        print(f"  person contacts (seed, who, t s, robot): {contacts}")
    visitor = sum(1 for r in results for i in r["intrusions"] if i.by == "robot"
                  and i.person == "visitor")
    print(f"  of the robot's intrusions, into the visitor's space: {visitor} (the visitor stands "
          f"in front of the robot at the start, in the way of rooms to the north)")
    print(f"personal-space intrusions (gap < 0.45 m, closing in): by the robot "
          f"{sum(r['intrusions_by_robot'] for r in results)} "
          f"({sum(r['intrusion_seconds_robot'] for r in results):.1f} s), by people "
          f"{sum(r['intrusions_by_person'] for r in results)} "
          f"({sum(r['intrusion_seconds_person'] for r in results):.1f} s); tours with any: "
          f"{sum(1 for r in results if r['intrusions_by_robot'] + r['intrusions_by_person'])}")
    print(f"max speed with someone within 1 m: "
          f"{max(r['max_speed_near_people'] for r in results):.2f} m/s (target <= 1.0)")
    if ratios:
        print(f"time to goal / full speed (max_speed) on the shortest path: median "
              f"{np.median(ratios):.2f}, p90 {np.percentile(ratios, 90):.2f}, max "
              f"{max(ratios):.2f} (target <= 1.5, issue 22)")
    print(f"localization error over {len(errors)} ticks: RMSE "
          f"{math.sqrt(float(np.mean(errors ** 2))):.3f} m, p95 {np.percentile(errors, 95):.3f} m, "
          f"max {errors.max():.3f} m; heading RMSE {math.sqrt(float(np.mean(headings ** 2))):.2f}°")
    time_split(results)
    print(f"global plans: {len(plan_ms)}, median {np.median(plan_ms):.1f} ms, p99 "
          f"{np.percentile(plan_ms, 99):.1f} ms, max {max(plan_ms):.1f} ms (target <= 100 ms)")


def time_split(results: list[dict]) -> None:
    """Where the tours' time went: per cause, the seconds spent and those beyond what the
    metres driven meanwhile take at full speed."""
    spent: dict[str, list[float]] = {}
    longer = 0.0
    for r in results:
        driven = sum(m for _, m in r.get("time_split", {}).values())
        longer += max(0.0, driven - r.get("shortest", driven)) / r.get("max_speed", 1.0)
        for cause, (seconds, metres) in r.get("time_split", {}).items():
            row = spent.setdefault(cause, [0.0, 0.0])
            row[0] += seconds
            row[1] += seconds - metres / r["max_speed"]
    if not spent:
        return
    total = sum(s for s, _ in spent.values())
    beyond = sum(b for _, b in spent.values())
    parts = ", ".join(f"{cause} {s:.0f} s (+{b:.0f} s)" for cause, (s, b) in
                      sorted(spent.items(), key=lambda kv: -kv[1][1]))
    print(f"time guiding {total:.0f} s, {beyond:.0f} s beyond full speed over the metres driven; "
          f"per cause, spent (beyond full speed): {parts}; the way driven longer than the "
          f"shortest path: +{longer:.0f} s at full speed")


def bench_buildings(args) -> None:
    """N tours in each of B generated buildings, reported per building and pooled."""
    import importlib.util
    import sys
    spec = importlib.util.spec_from_file_location(
        "buildings", Path(__file__).resolve().parent / "buildings.py")
    generator = importlib.util.module_from_spec(spec)
    sys.modules["buildings"] = generator
    spec.loader.exec_module(generator)
    from robots.profile import load_profile
    pooled, plan_ms, worst = [], [], []
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for b in range(args.first_building, args.first_building + args.buildings):
            map_path = generator.generate(b).save(folder)
            grid = load_map(map_path)
            shortest = GlobalPlanner(cost_map(grid, load_profile(args.robot).radius), cost_weight=0.0)
            rooms = sorted(name for name in grid.places if name.startswith("room_"))
            building_ms: list = []
            results = []
            for seed in range(args.first_tour, args.first_tour + args.tours):
                results.append(run_tour(args.robot, folder, seed, shortest, building_ms,
                                        building_tour(folder, map_path, rooms, shortest, seed)))
                if args.json:
                    save_tour(args.json, args.robot, b, results[-1], building_ms)
            print(f"\n== building {b} ({grid.shape[1] * grid.resolution:.0f} m × "
                  f"{grid.shape[0] * grid.resolution:.0f} m, {len(rooms)} rooms)")
            report(results, building_ms)
            worst.append((sum(r["success"] for r in results) / len(results), b))
            pooled += results
            plan_ms += building_ms
    print(f"\n== pooled: {args.buildings} buildings × {args.tours} tours, "
          f"{time.perf_counter() - started:.0f} s wall; load average {os.getloadavg()}")
    report(pooled, plan_ms)
    share, b = min(worst)
    print(f"worst building: {b}, {100 * share:.0f} % arrived with the visitor (target >= 98 %)")


KEPT = ("seed", "room", "outcome", "reason", "with_user", "success", "duration", "ratio",
        "time_split", "max_speed", "shortest",
        "contacts_wall", "contacts_person", "contacts_driving", "min_wall_clearance",
        "min_clearance_to_people", "intrusions_by_robot", "intrusions_by_person",
        "intrusion_seconds_robot", "intrusion_seconds_person", "max_speed_near_people")


def save_tour(path: str, robot: str, building: int, result: dict, plan_ms: list) -> None:
    """Append one tour's figures as a JSON line (with the building and the plans so far)."""
    import json
    row = {k: result[k] for k in KEPT}
    row.update(robot=robot, building=building, loc_errors=[round(e, 4) for e in
                                                           result["loc_errors"]],
               heading_errors=[round(e, 5) for e in result["heading_errors"]],
               plan_ms=[round(m, 2) for m in plan_ms],
               contacts=[vars(c) for c in result["contacts"]],
               intrusions=[vars(i) for i in result["intrusions"]])
    with open(path, "a") as out:
        out.write(json.dumps(row) + "\n")


def pool(files: list[str]) -> None:
    """Report tours saved by --json (several processes' files): per building, pooled, worst."""
    import json
    from types import SimpleNamespace
    rows = [json.loads(line) for f in files for line in Path(f).read_text().splitlines()
            if line.strip()]
    for row in rows:
        row["loc_errors"] = np.asarray(row["loc_errors"])
        row["heading_errors"] = np.asarray(row["heading_errors"])
        row["contacts"] = [SimpleNamespace(**c) for c in row["contacts"]]
        row["intrusions"] = [SimpleNamespace(**i) for i in row["intrusions"]]
    by_building: dict = {}
    for row in rows:
        by_building.setdefault((row["robot"], row["building"]), []).append(row)
    plans: dict = {}
    for (robot, b), results in sorted(by_building.items()):
        plan_ms = max((r["plan_ms"] for r in results), key=len)    # the building's last line
        plans[(robot, b)] = plan_ms
        print(f"\n== {robot}, building {b}: {len(results)} tours")
        report(results, plan_ms)
    for robot in sorted({r["robot"] for r in rows}):
        mine = [r for r in rows if r["robot"] == robot]
        shares = sorted((sum(r["success"] for r in results) / len(results), b, len(results))
                        for (who, b), results in by_building.items() if who == robot)
        print(f"\n== {robot} pooled: {len(shares)} buildings, {len(mine)} tours")
        report(mine, [m for (who, _), ms in plans.items() if who == robot for m in ms])
        share, b, n = shares[0]
        print(f"worst building: {b}, {100 * share:.0f} % of {n} tours arrived with the visitor "
              f"(target >= 98 %)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tours", type=int, default=100)
    parser.add_argument("--robot", default="horos")
    parser.add_argument("--ticks", type=int, default=300, help="ticks of the 10-people run")
    parser.add_argument("--buildings", type=int, default=0,
                        help="tour generated buildings instead of the office (N tours each)")
    parser.add_argument("--first-building", type=int, default=0,
                        help="the first generated building (seed) of --buildings")
    parser.add_argument("--first-tour", type=int, default=0, help="the first tour (seed)")
    parser.add_argument("--json", help="with --buildings: append one line per tour to FILE")
    parser.add_argument("--pool", nargs="+", metavar="FILE",
                        help="report the tours that --json files hold, together")
    args = parser.parse_args()
    if args.pool:
        pool(args.pool)
        return
    print(f"load average before: {os.getloadavg()}")
    if args.buildings:
        bench_buildings(args)
        return
    shortest = GlobalPlanner(cost_map(load_map("office"), 0.26), cost_weight=0.0)
    plan_ms: list = []
    results = []
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for seed in range(args.tours):
            results.append(run_tour(args.robot, folder, seed, shortest, plan_ms))
        print(f"{args.robot}, {args.tours} tours in {time.perf_counter() - started:.0f} s wall; "
              f"load average {os.getloadavg()}")
        report(results, plan_ms)
        bench_tick(args.robot, folder, args.ticks)
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
