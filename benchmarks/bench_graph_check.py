"""Load and fully check a generated state graph, and time the survey's conditions per tick.

- `load+check`: a graph.xml with 1,000 states and 5,000 transitions is parsed safely, read,
  every condition compiled, and every check run — including the pairwise overlap analysis of
  each state's outgoing conditions (here all exclusive, the slowest case: every pair is proved).
  Target: ≤ 1 s.
- `tick`: evaluating the survey's outgoing conditions of one state, as the state machine does
  once per tick, with realistic percept values.

    python benchmarks/bench_graph_check.py [--states 1000] [--per-state 5] [--repeat 5]
"""
from __future__ import annotations

import argparse
import random
import statistics
import tempfile
import time
from pathlib import Path

from applications.graph.loader import check_application, load_application

def bands(count: int, rng: random.Random) -> list[tuple[int, int]]:
    """`count` adjacent, non-overlapping ranges of people.count with random edges."""
    edges = sorted(rng.sample(range(1, 60), count - 1))
    bounds = [0, *edges, 1000]
    return list(zip(bounds, bounds[1:]))


def condition(low: int, high: int, rng: random.Random) -> str:
    """Conditions exclusive by their people.count band, mixing percepts, units and time."""
    pick = rng.randrange(3)
    if pick == 0:
        return f"people.count >= {low} and people.count &lt; {high}"
    if pick == 1:
        return (f"user.present and user.distance >= {low * 10}cm and "
                f"user.distance &lt; {high * 10}cm and people.count >= {low} and "
                f"people.count &lt; {high}")
    return (f"(time_in_state >= {low}s and time_in_state &lt; {high}s or survey.done) and "
            f"people.count >= {low} and people.count &lt; {high}")


def generated_graph(states: int, per_state: int, seed: int = 0) -> str:
    rng = random.Random(seed)
    behaviors = ["Idle", "FaceUser", "Survey", "CallBack", "AttractAttention"]
    lines = ['<application name="generated" initial="S0" robot="horos">']
    for index in range(states):
        lines.append(f'  <state name="S{index}" behavior="{behaviors[index % 5]}">')
        targets = [(index + 1) % states] + [rng.randrange(states) for _ in range(per_state - 1)]
        for (low, high), target in zip(bands(per_state, rng), targets):
            lines.append(f'    <transition to="S{target}" when="{condition(low, high, rng)}"/>')
        lines.append("  </state>")
    lines.append("</application>")
    return "\n".join(lines) + "\n"


def time_load_and_check(states: int, per_state: int, repeat: int) -> tuple[list[float], list[float]]:
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "graph.xml").write_text(generated_graph(states, per_state))
        application, diagnostics = check_application(folder)    # warm-up, and a sanity check
        assert application is not None, "\n".join(map(str, diagnostics[:5]))
        assert sum(len(s.transitions) for s in application.states.values()) == states * per_state
        wall, cpu = [], []
        for _ in range(repeat):
            start, start_cpu = time.perf_counter(), time.process_time()
            check_application(folder)
            wall.append(time.perf_counter() - start)
            cpu.append(time.process_time() - start_cpu)
    return wall, cpu


def time_survey_ticks(ticks: int = 100_000) -> dict[str, float]:
    """Seconds per tick to evaluate each survey state's outgoing conditions, with percepts that
    make none fire (the common case: every condition is evaluated)."""
    values = {"people.count": 1, "people.new": 0, "user.present": True, "user.distance": 1.4,
              "survey.done": False}
    costs = {}
    for name, state in load_application("survey").states.items():
        transitions = state.ordered_transitions()
        start = time.perf_counter()
        for _ in range(ticks):
            for transition in transitions:
                if transition.condition.evaluate(values, 3.0):
                    break
        costs[name] = (time.perf_counter() - start) / ticks
    return costs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=1000)
    parser.add_argument("--per-state", type=int, default=5)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    wall, cpu = time_load_and_check(args.states, args.per_state, args.repeat)
    print(f"load+check {args.states} states, {args.states * args.per_state} transitions: "
          f"median {statistics.median(wall):.3f} s wall ({statistics.median(cpu):.3f} s CPU), "
          f"min {min(wall):.3f} s (target ≤ 1 s) over {args.repeat} runs")
    costs = time_survey_ticks()
    print("survey conditions per tick: " + ", ".join(
        f"{name} {cost * 1e6:.2f} µs" for name, cost in costs.items()))


if __name__ == "__main__":
    main()
