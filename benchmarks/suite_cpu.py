"""Where the test suite's CPU goes: per test file, the CPU-seconds its tests took, so work on
the suite's time (issue 21: `bash .ci/run` in 5 minutes on two cores) goes where the time is.

Runs the suite the way `.ci/run` does (`pytest -n auto --dist worksteal`) with this file as a
pytest plugin in every worker. Per test it records the worker's own CPU (all its threads: the
simulated robot, the emulators, the drivers) and the CPU of the child processes the test waited
for (`interbot` processes, campaign workers, pip), then prints the files by total CPU, and the
share of the whole-application runs that several tests share (tests/applications/app_runs.py:
the first test that needs a run pays for it).

    python benchmarks/suite_cpu.py [--top 30] [pytest arguments, e.g. tests/skills]

Then the tests that hold a worker longest beyond their CPU (real-time waits).

CPU-seconds are the machine-independent part of the suite's time: on two cores the suite
cannot finish in less than about half its CPU-seconds, whatever the number of workers.
Processes a test starts but does not wait for (Ray's, Chromium) are not counted.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

OUT_VARIABLE = "INTERBOT_SUITE_CPU_DIR"     # where the workers write one line per test
ROOT = Path(__file__).resolve().parent.parent
SHARED_RUNS = ("test_bundled_states.py", "test_portability.py", "test_guide_end_to_end.py",
               "test_shopping_end_to_end.py", "test_survey_end_to_end.py")


# ------------------------------------------------------------------ the plugin (in the workers)

def _cpu() -> tuple[float, float]:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime, children.ru_utime + children.ru_stime


def pytest_runtest_protocol(item, nextitem):
    """Wraps each test (set-up, call and tear-down) with CPU readings; returns None so pytest
    runs the test as usual."""
    folder = os.environ.get(OUT_VARIABLE)
    if folder:
        item.config._suite_cpu_start = (_cpu(), time.monotonic(), time.time())


def pytest_runtest_makereport(item, call):
    """After the tear-down phase, one line per test: own CPU, waited children's CPU, wall,
    when it began (seconds since the epoch, the same clock in every worker), the worker."""
    folder = os.environ.get(OUT_VARIABLE)
    start = getattr(item.config, "_suite_cpu_start", None)
    if not folder or start is None or call.when != "teardown":
        return
    (own0, children0), wall0, began = start
    own, children = _cpu()
    line = json.dumps([item.nodeid, round(own - own0, 3), round(children - children0, 3),
                       round(time.monotonic() - wall0, 3), round(began, 3),
                       os.environ.get("PYTEST_XDIST_WORKER", "-")])
    with open(Path(folder) / f"worker-{os.getpid()}.jsonl", "a") as handle:
        handle.write(line + "\n")


# ------------------------------------------------------------------ the report

def run_suite(pytest_args: list[str], folder: Path) -> int:
    env = dict(os.environ, **{OUT_VARIABLE: str(folder)})
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "benchmarks"),
                                                      env.get("PYTHONPATH", "")]))
    command = [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-p", "suite_cpu",
               "-n", "auto", "--dist", "worksteal"] + pytest_args
    return subprocess.run(command, cwd=ROOT, env=env).returncode


def read_rows(folder: Path) -> list[tuple[str, float, float, float, float, str]]:
    rows = []
    for path in sorted(folder.glob("worker-*.jsonl")):
        rows += [tuple(json.loads(line)) for line in path.read_text().splitlines() if line]
    return rows


def report(rows, top: int, wall: float) -> None:
    by_file: dict[str, list[float]] = defaultdict(lambda: [0.0, 0.0, 0])
    for nodeid, own, children, *_ in rows:
        entry = by_file[nodeid.split("::")[0]]
        entry[0] += own
        entry[1] += children
        entry[2] += 1
    own_total = sum(r[1] for r in rows)
    children_total = sum(r[2] for r in rows)
    total = own_total + children_total
    print(f"{len(rows)} tests, {total:.0f} CPU-s ({own_total:.0f} in the workers, "
          f"{children_total:.0f} in processes they waited for), {wall:.0f} s wall")
    shared = sum(v[0] + v[1] for f, v in by_file.items() if f.endswith(SHARED_RUNS))
    print(f"files reading the shared whole-application runs: {shared:.0f} CPU-s "
          f"({100 * shared / max(total, 1e-9):.0f} %)")
    print(f"{'CPU-s':>7} {'share':>6} {'workers':>8} {'children':>8} {'tests':>5}  file")
    ranked = sorted(by_file.items(), key=lambda kv: -(kv[1][0] + kv[1][1]))
    for name, (own, children, count) in ranked[:top]:
        cpu = own + children
        print(f"{cpu:7.1f} {100 * cpu / max(total, 1e-9):5.1f}% {own:8.1f} {children:8.1f} "
              f"{count:5d}  {name}")
    report_waiting(rows, top)
    report_timeline(rows, wall)


def report_timeline(rows, wall: float) -> None:
    """How the wall clock went: start-up and collection before the first test, and the tail:
    from the moment the first worker had no test left to the end of the last one (on two cores
    a worker with nothing left is half the machine idle unless the others can use it)."""
    first = min(row[4] for row in rows)
    last_end: dict[str, float] = defaultdict(float)
    for row in rows:
        worker = row[5] if len(row) > 5 else "-"
        last_end[worker] = max(last_end[worker], row[4] + row[3])
    ends = sorted(last_end.values())
    print(f"wall clock: {wall:.0f} s; {wall - (ends[-1] - first):.0f} s outside the tests "
          f"(start-up, collection, the end); the {len(ends)} workers ran out of tests "
          f"{ends[0] - first:.0f} s to {ends[-1] - first:.0f} s after the first began")


def report_waiting(rows, top: int) -> None:
    """The tests that hold a worker longest beyond their CPU (real-time waits: timeouts, links
    going silent, a browser). A worker waiting is a core lent to the others only while other
    workers have computing to do; at the end of the run it is time the suite waits."""
    waiting = sorted(rows, key=lambda row: -(row[3] - row[1] - row[2]))[:top]
    print(f"tests waiting longest beyond their CPU (wall - CPU; wall includes waiting for a core):")
    print(f"{'wait-s':>7} {'wall-s':>7} {'CPU-s':>6}  test")
    for nodeid, own, children, wall, *_ in waiting:
        print(f"{wall - own - children:7.1f} {wall:7.1f} {own + children:6.1f}  {nodeid}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--top", type=int, default=30, help="files to list (default 30)")
    args, pytest_args = parser.parse_known_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        started = time.monotonic()
        status = run_suite(pytest_args, Path(folder))
        wall = time.monotonic() - started
        rows = read_rows(Path(folder))
    if not rows:
        print("no test reported its CPU (did pytest collect any?)", file=sys.stderr)
        return status or 1
    report(rows, args.top, wall)
    return status


if __name__ == "__main__":
    sys.exit(main())
