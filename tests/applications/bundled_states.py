"""The states every bundled scenario goes through on every robot, kept as data.

`bundled_states.json` beside this file holds, per application, robot and scenario, the sequence
of states of a `--fast` run with seed 0. It was written from the code before the tick was made
faster (issue 21), so a change that is meant to leave behaviour alone (a cheaper update rule, a
faster ray caster, a parallel test run) is checked against what the robots did before it:
`tests/applications/test_bundled_states.py` compares. A change that is meant to alter what the
robots do rewrites the file on purpose, and says why in its commit:

    python -m tests.applications.bundled_states --write [--jobs 2]
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import applications

BUNDLED = Path(applications.__file__).parent / "bundled"
STATES_FILE = Path(__file__).with_name("bundled_states.json")
ROBOTS = {                 # the robots each bundled application is run on
    "survey": ("horos", "perses", "argos"),
    "guide": ("horos", "perses", "argos"),
    "receptionist": ("horos", "perses", "argos"),
    "shopping": ("perses", "horos"),
}


def cases() -> list[tuple[str, str, str]]:
    """(application, robot, scenario) for every bundled scenario on every robot it runs on."""
    return [(app, robot, scenario.stem)
            for app, robots in ROBOTS.items()
            for scenario in sorted((BUNDLED / app / "scenarios").glob("*.toml"))
            for robot in robots]


def key(app: str, robot: str, scenario: str) -> str:
    return f"{app}/{robot}/{scenario}"


def states_of(trace: list[dict]) -> list[str]:
    return [event["to"] for event in trace if event["kind"] == "transition"]


def run_states(case: tuple[str, str, str]) -> tuple[str, list[str]]:
    """Run one case in this process, the way the shared test runs are made, and return its states."""
    from tests.applications.app_runs import AppRuns
    with tempfile.TemporaryDirectory() as folder:
        run = AppRuns(Path(folder)).run(*case)
        if run.code != 0:
            raise RuntimeError(f"{key(*case)} exited {run.code}")
        return key(*case), states_of(run.trace)


def load() -> dict[str, list[str]]:
    return json.loads(STATES_FILE.read_text())


def write(jobs: int) -> None:
    with ProcessPoolExecutor(jobs) as pool:
        found = dict(pool.map(run_states, cases()))
    STATES_FILE.write_text(json.dumps(found, indent=1, sort_keys=True) + "\n")
    print(f"wrote the states of {len(found)} runs to {STATES_FILE}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="run every case and write the file")
    parser.add_argument("--jobs", type=int, default=2)
    options = parser.parse_args()
    if not options.write:
        parser.print_help()
        sys.exit(2)
    write(options.jobs)
