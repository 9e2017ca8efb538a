"""The whole tick of each bundled application, in --fast mode, as `interbot run` runs it.

Each workload is the real command line (`interbot run APP --fast --quiet`, in this process)
with the real drivers talking their wire protocols to the emulators:

- survey_idle:  the survey on HOROS, its default scenario (people only at the start), 60 min;
- survey_crowd: the survey with ten more people walking the hallway back and forth, 10 min;
- guide_crowd:  the guide on HOROS, a visitor asking for room N2 and following the robot there,
                with ten people walking the hallway, 10 min;
- shopping:     the shopping assistant on PERSES following a customer, with ten shoppers (half
                with carts) walking between the shelves, 10 min.

Printed per workload: the median and p99 of the tick (wall clock from one `sense` to the next:
everything the loop does, on every thread it waits for), the median CPU time of a tick (the
process's, all threads: it does not count the waits for a busy machine's cores, so two commits
run alternately compare by it when other work shares the machine), the share of each layer and each
skill in it (time inside each, not counting what it called that is counted elsewhere: a skill
reading the simulated laser counts the ray casting to L0), and the ratio to a baseline run in
the same process just before: the same workload with localization weighing every scan, the
update rule before issue 21.

    python benchmarks/bench_tick.py [--minutes-scale 1.0] [--only survey_idle,guide_crowd]
                                    [--robot argos]

Benchmarks are not a layer: this script wraps methods of every layer to time them.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import os
import re
import tempfile
import threading
import time
from collections import Counter
from contextlib import contextmanager
from pathlib import Path

import numpy as np

import applications
from applications.cli import main as interbot
from applications.statemachine import StateMachine
from applications.trace import TraceWriter
from behaviors.active import ActiveBehavior
from behaviors.percept_view import PerceptTracker
from behaviors.robot import Robot
from robots.hardware import Hardware
from robots.sim.devices import SimLaser, SimPersonDetector
from skills.skill import Skill
from skills.skillset import SkillSet
from skills.localization import Localization

BUNDLED = Path(applications.__file__).parent / "bundled"
TARGETS_MS = {"survey_idle": 0.6, "survey_crowd": 1.2, "guide_crowd": 1.5, "shopping": 1.5}


# -- workloads ----------------------------------------------------------------------------------

def hallway_walkers(count: int = 10) -> str:
    """People pacing the office hallway back and forth at different speeds and offsets."""
    out = []
    for i in range(count):
        y = -0.45 + 0.1 * i
        legs = ", ".join(["[9.0, %.2f], [-9.0, %.2f]" % (y, y)] * 30)
        out.append(f'[[person]]\nid = "walker{i}"\nappear = 0.0\nat = [{-9.0 + 1.8 * i:.1f}, '
                   f'{y:.2f}]\nspeed = {0.6 + 0.08 * i:.2f}\nsteps = [ {{ walk = [{legs}] }} ]\n')
    return "\n".join(out)


def store_shoppers(count: int = 10) -> str:
    """Shoppers visiting random shelves, every second one with a cart."""
    return "\n".join(
        f'[[person]]\nid = "shopper{i}"\nappear = 0.0\nat = "street"\nspeed = {0.7 + 0.06 * i:.2f}\n'
        f'cart = {"true" if i % 2 == 0 else "false"}\n'
        f'steps = [ {{ shop = "shelf_", count = 80, dwell = [1.0, 4.0] }} ]\n'
        for i in range(count))


def scenario(folder: Path, app: str, name: str, duration: float, extra: str) -> Path:
    """The bundled scenario with its duration set and `extra` people added."""
    text = (BUNDLED / app / "scenarios" / f"{name}.toml").read_text()
    text = re.sub(r"(?m)^duration\s*=.*$", f"duration = {duration}", text, count=1)
    path = folder / f"{app}-{name}-{len(extra)}.toml"
    path.write_text(text + "\n" + extra)
    return path


def workloads(folder: Path, scale: float) -> dict[str, list[str]]:
    minutes = {"survey_idle": 60, "survey_crowd": 10, "guide_crowd": 10, "shopping": 10}
    seconds = {name: round(m * 60 * scale) for name, m in minutes.items()}
    return {
        "survey_idle": ["survey", "--robot", "horos", "--scenario",
                        str(scenario(folder, "survey", "default", seconds["survey_idle"], ""))],
        "survey_crowd": ["survey", "--robot", "horos", "--scenario",
                         str(scenario(folder, "survey", "default", seconds["survey_crowd"],
                                      hallway_walkers()))],
        "guide_crowd": ["guide", "--robot", "horos", "--scenario",
                        str(scenario(folder, "guide", "follows", seconds["guide_crowd"],
                                     hallway_walkers()))],
        "shopping": ["shopping", "--robot", "perses", "--scenario",
                     str(scenario(folder, "shopping", "follow_me", seconds["shopping"],
                                  store_shoppers()))],
    }


# -- timing -------------------------------------------------------------------------------------

class Probe:
    """Exclusive time per label on the main thread: a timed call's own time, less the time of
    the timed calls inside it. Ticks are the intervals between successive `Robot.sense` calls."""

    def __init__(self) -> None:
        self.own: Counter = Counter()
        self.ticks: list[float] = []
        self.cpu: list[float] = []         # the process's CPU time of each tick (all threads)
        self._last_cpu: float | None = None
        self._stack: list[float] = []
        self._main = threading.get_ident()
        self._last_sense: float | None = None
        self._undo: list[tuple[type, str, object]] = []

    def wrap(self, cls: type, name: str, label) -> None:
        """Time `cls.name` under `label` (a string, or a function of the instance)."""
        original = cls.__dict__[name]
        probe = self

        def timed(this, *args, **kwargs):
            if threading.get_ident() != probe._main:
                return original(this, *args, **kwargs)
            start = time.perf_counter()
            probe._stack.append(0.0)
            try:
                return original(this, *args, **kwargs)
            finally:
                elapsed = time.perf_counter() - start
                nested = probe._stack.pop()
                probe.own[label if isinstance(label, str) else label(this)] += elapsed - nested
                if probe._stack:
                    probe._stack[-1] += elapsed
        setattr(cls, name, timed)
        self._undo.append((cls, name, original))

    def mark_tick(self) -> None:
        now, cpu = time.perf_counter(), time.process_time()
        if self._last_sense is not None:
            self.ticks.append(now - self._last_sense)
            self.cpu.append(cpu - self._last_cpu)
        self._last_sense, self._last_cpu = now, cpu

    def undo(self) -> None:
        for cls, name, original in reversed(self._undo):
            setattr(cls, name, original)


def skill_classes() -> list[type]:
    """Every skill class with its own `sense` (the L1 senses of the tick)."""
    found, todo = [], [Skill]
    while todo:
        cls = todo.pop()
        todo.extend(cls.__subclasses__())
        if "sense" in cls.__dict__ and cls is not Skill:
            found.append(cls)
    return found


@contextmanager
def probed():
    probe = Probe()
    original_sense = Robot.__dict__["sense"]

    def sense(this):
        probe.mark_tick()
        return original_sense(this)
    Robot.sense = sense
    probe.wrap(Hardware, "sense", "L0 world, emulator and driver")
    probe.wrap(SimLaser, "read", "L0 devices (laser, camera)")
    probe.wrap(SimPersonDetector, "detect", "L0 devices (laser, camera)")
    for cls in skill_classes():
        probe.wrap(cls, "sense", lambda skill: f"L1 {skill.name}")
    probe.wrap(SkillSet, "act", "L1 motion and safety, L0 command")
    probe.wrap(PerceptTracker, "view", "L2 percepts")
    probe.wrap(ActiveBehavior, "tick", "L2 behavior tree")
    probe.wrap(StateMachine, "step", "L3 state machine")
    probe.wrap(TraceWriter, "write", "L3 trace")
    try:
        yield probe
    finally:
        Robot.sense = original_sense
        probe.undo()


@contextmanager
def every_scan():
    """The localization update rule before issue 21: a scan weighed on every tick."""
    saved = {name: getattr(Localization, name) for name in
             ("UPDATE_AFTER_MOVING", "UPDATE_AFTER_TURNING", "UPDATE_EVERY_STANDING",
              "STANDING_SPEED", "STANDING_TURN_RATE")}
    for name in saved:
        setattr(Localization, name, 0.0)
    try:
        yield
    finally:
        for name, value in saved.items():
            setattr(Localization, name, value)


def run_once(args: list[str], folder: Path) -> dict:
    with probed() as probe:
        start = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()) as said:
            code = interbot(["run", *args, "--fast", "--quiet", "--data", str(folder)])
        wall = time.perf_counter() - start
    ticks = np.array(probe.ticks) * 1000
    if code != 0 or len(ticks) == 0:
        raise SystemExit(f"interbot run {' '.join(args)} exited {code}:\n{said.getvalue()}")
    total = float(ticks.sum())
    shares = {label: 100 * 1000 * own / total for label, own in probe.own.items()}
    shares["rest of the loop"] = max(0.0, 100 - sum(shares.values()))
    return {"median": float(np.median(ticks)), "p99": float(np.percentile(ticks, 99)),
            "cpu": float(np.median(probe.cpu)) * 1000,
            "ticks": len(ticks), "wall": wall, "shares": shares}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes-scale", type=float, default=1.0,
                        help="scale every workload's simulated time (0.1: a tenth)")
    parser.add_argument("--only", help="comma-separated workloads")
    parser.add_argument("--no-baseline", action="store_true")
    parser.add_argument("--robot", help="run every workload on this robot instead (e.g. argos, "
                        "the CAN base)")
    options = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as folder:
        jobs = workloads(Path(folder), options.minutes_scale)
        if options.robot:
            for args in jobs.values():
                args[args.index("--robot") + 1] = options.robot
        names = options.only.split(",") if options.only else list(jobs)
        for name in names:
            base = None
            if not options.no_baseline:
                with every_scan():
                    base = run_once(jobs[name], Path(folder) / f"{name}-base")
            now = run_once(jobs[name], Path(folder) / name)
            report(name, now, base)
    print(f"load average after: {os.getloadavg()[0]:.2f}")


def report(name: str, now: dict, base: dict | None) -> None:
    target = TARGETS_MS[name]
    print(f"\n{name}: {now['ticks']} ticks in {now['wall']:.1f} s; tick median "
          f"{now['median']:.3f} ms, p99 {now['p99']:.3f} ms (target median <= {target} ms: "
          f"{'met' if now['median'] <= target else 'MISSED by %.0f %%' % (100 * (now['median'] / target - 1))})")
    print(f"  CPU per tick (the process, every thread): median {now['cpu']:.3f} ms; steadier than "
          f"the wall clock on a loaded machine, so compare commits by it, run alternately")
    if base is not None:
        print(f"  baseline (a scan weighed every tick): median {base['median']:.3f} ms, p99 "
              f"{base['p99']:.3f} ms; ratio now / baseline: median "
              f"{now['median'] / base['median']:.2f}, p99 {now['p99'] / base['p99']:.2f}")
    for label, share in sorted(now["shares"].items(), key=lambda item: -item[1]):
        if share >= 0.5:
            print(f"  {share:5.1f} %  {label}")


if __name__ == "__main__":
    main()
