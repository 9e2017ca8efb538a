"""The survey with 10 simulated people for 10 minutes of robot time, in --fast mode.

Prints ticks per second, the median and p99 cost of a full tick, each layer's share, and the
speed-up over real time at 10 Hz, for two set-ups measured in the same run:

- `p2os-pty`: the default simulated HOROS — the real P2OS driver talks to the firmware
  emulator over a pseudo-terminal, in lock-step with the simulated clock;
- `in-process` (baseline): the same world behind the in-process simulated base, no protocol.

    python benchmarks/bench_survey.py [--minutes 10] [--people 10] [--seed 0]

Benchmarks are not a layer: this script imports every layer to time each one.
"""
from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections import defaultdict
from pathlib import Path

from applications.graph.loader import load_application
from applications.runtime import TICK, Run
from behaviors.robot import Robot
from robots.hardware import Hardware, open_hardware
from skills.skillset import SkillSet


def scenario_text(people: int, minutes: float) -> str:
    """People arriving every so often; every third takes the survey, the others walk past."""
    duration = minutes * 60
    lines = ["[scenario]", 'name = "bench"', f"duration = {duration}", 'robot = "robot_home"', ""]
    spacing = duration / (people + 1)
    for i in range(people):
        appear = 20 + i * spacing
        side = 1 if i % 2 == 0 else -1
        lines += ["[[person]]", f'id = "p{i}"', f"appear = {appear:.1f}",
                  f"at = [{9.5 * side}, {0.2 + 0.1 * (i % 5):.1f}]", "speed = 1.0"]
        if i % 3 == 0:
            lines.append(f'steps = [{{ walk = [[{2.5 * side}, 0.2]] }}, {{ pause = 2.0 }}, '
                         f'{{ approach = 0.5 }}, {{ answer = ["yes", "3", "no"], delay = 2.0 }}, '
                         f'{{ walk = [[{1.0 * side}, 0.6]] }}, {{ leave = [{-9.5 * side}, 0.6] }}]')
        else:
            lines.append(f"steps = [{{ leave = [{-9.5 * side}, 0.5] }}]")
        lines.append("")
    return "\n".join(lines)


class LayerTimer:
    """Wraps methods to add their wall time to a layer's account for the current tick."""

    def __init__(self) -> None:
        self.current = defaultdict(float)
        self.per_tick: list[dict[str, float]] = []
        self.totals: list[float] = []

    def wrap(self, owner, name: str, layer: str, subtract_from: str | None = None) -> None:
        original = getattr(owner, name)
        timer = self

        def timed(*args, **kwargs):
            start = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                spent = time.perf_counter() - start
                timer.current[layer] += spent
                if subtract_from:
                    timer.current[subtract_from] -= spent
        setattr(owner, name, timed)

    def tick_done(self, total: float) -> None:
        self.per_tick.append(dict(self.current))
        self.totals.append(total)
        self.current = defaultdict(float)


def instrumented_robot(hardware: Hardware, timer: LayerTimer) -> Robot:
    skills = SkillSet(hardware)
    # L0: bringing the world and the link up to date, and sending the command
    timer.wrap(hardware, "sense", "L0 robots", subtract_from="L1 skills")
    timer.wrap(hardware.base, "command", "L0 robots", subtract_from="L1 skills")
    # L1: skills sensing and acting (minus the L0 calls inside them)
    timer.wrap(skills, "sense", "L1 skills", subtract_from="L2 behaviors")
    timer.wrap(skills, "act", "L1 skills", subtract_from="L2 behaviors")
    robot = Robot(skills)
    # L2: the percept view and the active tree's tick (minus the L1 calls inside)
    timer.wrap(robot, "sense", "L2 behaviors", subtract_from="L3 applications")
    timer.wrap(robot, "act", "L2 behaviors", subtract_from="L3 applications")
    return robot


def measure(label: str, scenario: Path, minutes: float, seed: int, emulate: bool) -> dict:
    hardware = open_hardware("horos", scenario=scenario, fast=True, seed=seed, emulate=emulate)
    timer = LayerTimer()
    robot = instrumented_robot(hardware, timer)
    wait_until = robot.wait_until
    last = [time.perf_counter()]

    def tick_boundary(t: float) -> None:
        now = time.perf_counter()
        total = now - last[0]
        below = sum(v for k, v in timer.current.items() if k != "L3 applications")
        timer.current["L3 applications"] = total - below   # the state machine, dialog, trace
        timer.tick_done(total)
        wait_until(t)
        last[0] = time.perf_counter()

    robot.wait_until = tick_boundary
    app = load_application("survey")
    try:
        start = time.perf_counter()
        summary = Run(app, robot, duration=minutes * 60, echo=None).run()
        wall = time.perf_counter() - start
    finally:
        robot.close()
    totals = sorted(timer.totals)
    shares = defaultdict(float)
    for tick in timer.per_tick:
        for layer, spent in tick.items():
            shares[layer] += spent
    spent_all = sum(shares.values())
    median = statistics.median(totals)
    slow = [tick for tick, total in zip(timer.per_tick, timer.totals)
            if total >= totals[int(0.99 * (len(totals) - 1))]]
    slow_share = {k: statistics.mean(t.get(k, 0.0) for t in slow) * 1e3 for k in shares}
    return {
        "label": label, "ticks": summary.ticks, "wall": wall,
        "ticks_per_s": summary.ticks / wall,
        "median_ms": median * 1e3,
        "p99_ms": totals[int(0.99 * (len(totals) - 1))] * 1e3,
        "speedup": TICK / median,
        "shares": {k: v / spent_all for k, v in sorted(shares.items())},
        "surveys": summary.surveys_completed,
        "slow_ms": slow_share,
        "states": dict(summary.time_in_state),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--people", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        scenario = Path(folder) / "bench.toml"
        scenario.write_text(scenario_text(args.people, args.minutes))
        results = [measure("p2os-pty", scenario, args.minutes, args.seed, emulate=True),
                   measure("in-process", scenario, args.minutes, args.seed, emulate=False)]
    print(f"survey, HOROS, {args.people} people, {args.minutes:g} min of robot time, --fast")
    for r in results:
        print(f"\n[{r['label']}] {r['ticks']} ticks in {r['wall']:.2f} s: {r['ticks_per_s']:.0f} ticks/s; "
              f"tick median {r['median_ms']:.3f} ms, p99 {r['p99_ms']:.3f} ms; "
              f"{r['speedup']:.0f}x real time at 10 Hz; surveys completed: {r['surveys']}")
        print("  share of tick time: " + ", ".join(f"{k} {v:.0%}" for k, v in r["shares"].items()))
        print("  slowest 1% of ticks, mean ms per layer: "
              + ", ".join(f"{k} {v:.2f}" for k, v in sorted(r["slow_ms"].items())))
    pty, base = results
    print(f"\nratio p2os-pty / in-process (median tick): {pty['median_ms'] / base['median_ms']:.2f}")


if __name__ == "__main__":
    main()
