"""Is a change exact? Record bundled runs with two source trees and compare them tick by tick.

A speed-up that is meant to leave behaviour alone (issue 21) must leave every run the same,
not only the states the kept-states test compares. Each case is run once per tree,

    interbot run APP --robot R --scenario S --fast --quiet --seed 0 --record FILE

with that tree first on the import path, and the two recordings are read back with
`applications.recording.read_ticks` and compared message by message. What differs between two
runs of one tree is left out: wall-clock fields, the pty's name, and the clock reads (`["now",
t]`) a driver makes while it waits for its emulator. Prints per case the first difference (or
SAME) and each run's CPU; exits 1 when any case differs.

    python benchmarks/same_run.py OLD_TREE NEW_TREE [APP/ROBOT/SCENARIO ...]

OLD_TREE is typically a `git archive` of the commit before the change, unpacked; NEW_TREE the
working tree. The CPU figures include the recorder's cost: measure speed with
`benchmarks/bench_tick.py` instead.
"""
from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_CASES = ["shopping/perses/follow_me", "shopping/horos/hidden",
                 "guide/argos/group_blocking", "guide/horos/follows", "survey/horos/default",
                 "survey/perses/nobody", "receptionist/argos/visitor"]
WALL_CLOCK = {"elapsed", "wall", "wall_time", "cpu"}
PTY_NAME = re.compile(r"/dev/pts/\d+")


def record(tree: Path, case: str, out: Path) -> float:
    """Run `case` with `tree`'s code, recording to `out`; the run's CPU-seconds."""
    app, robot, scenario = case.split("/")
    env = dict(os.environ, PYTHONPATH=str(tree))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-m", "applications.cli", "run", app, "--robot", robot,
                    "--scenario", scenario, "--fast", "--quiet", "--seed", "0",
                    "--record", str(out), "--data", str(out.with_suffix(".data"))],
                   env=env, cwd=tree, check=True, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def strip(value):
    """`value` without what varies between two runs of one tree."""
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items() if k not in WALL_CLOCK}
    if isinstance(value, list):
        return [strip(v) for v in value if not (isinstance(v, list) and v and v[0] == "now")]
    if isinstance(value, str) and "/dev/pts/" in value:
        return PTY_NAME.sub("/dev/pts/N", value)
    return value


def first_difference(a, b, where: str = "") -> str | None:
    """Where two decoded messages first differ (a path like `tick 3.pose[1]`), or None."""
    if type(a) is not type(b):
        return f"{where}: {a!r:.120} != {b!r:.120}"
    if isinstance(a, dict):
        for key in sorted(set(a) | set(b), key=str):
            if key not in a or key not in b:
                return f"{where}.{key}: only in {'new' if key in b else 'old'}"
            found = first_difference(a[key], b[key], f"{where}.{key}")
            if found:
                return found
        return None
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{where}: length {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            found = first_difference(x, y, f"{where}[{i}]")
            if found:
                return found
        return None
    return None if a == b else f"{where}: {a!r:.120} != {b!r:.120}"


def compare(old_ticks, new_ticks) -> str | None:
    """The first difference between two runs' ticks (lists of decoded messages), or None.
    Two runs without a tick are not the same run: nothing was compared."""
    old_ticks, new_ticks = list(old_ticks), list(new_ticks)
    if not old_ticks or not new_ticks:
        return f"no ticks recorded (old {len(old_ticks)}, new {len(new_ticks)})"
    for n, (a, b) in enumerate(zip(old_ticks, new_ticks)):
        found = first_difference(strip(a), strip(b), f"tick {n}")
        if found:
            return found
    if len(old_ticks) != len(new_ticks):
        return f"ticks {len(old_ticks)} != {len(new_ticks)}"
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old", type=Path, help="the source tree before the change")
    parser.add_argument("new", type=Path, help="the source tree after it")
    parser.add_argument("cases", nargs="*", default=DEFAULT_CASES,
                        help="APP/ROBOT/SCENARIO (default: moving and idle runs, three bases)")
    args = parser.parse_args(argv)
    from applications.recording import read_ticks
    differing = 0
    with tempfile.TemporaryDirectory(prefix="same_run_") as folder:
        for case in args.cases:
            name = case.replace("/", "-")
            old, new = Path(folder) / f"old-{name}.mcap", Path(folder) / f"new-{name}.mcap"
            cpu_old, cpu_new = record(args.old, case, old), record(args.new, case, new)
            found = compare(read_ticks(old), read_ticks(new))
            differing += found is not None
            print(f"{case:32s} cpu old {cpu_old:6.2f} s new {cpu_new:6.2f} s "
                  f"({100 * (cpu_new / max(cpu_old, 1e-9) - 1):+5.1f} %)  "
                  f"{'SAME' if found is None else 'DIFFERENT at ' + found}", flush=True)
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
