"""The laser on its wire: with [laser] device = "lms200:sim" the applications read the laser
through the LMS driver and its emulator in the simulated world (lock-step, --fast), and reach
the same states as with the in-process simulated laser, on HOROS and on PERSES."""
from __future__ import annotations

from pathlib import Path

import pytest

from applications.appfolder import load_folder
from applications.database import ApplicationDatabase
from applications.graph.loader import find_application
from applications.runtime import Run
from applications.trace import TraceWriter, read_trace
from behaviors.robot import open_robot
from robots.lms2xx.driver import LMS2xxLaser
from robots.profile import PROFILE_DIR

# One scenario: every scenario with the laser (and every other device) on its wire is
# test_portability's --wire test; this one keeps the profile's route (device = "lms200:sim").
CASES = [("survey", "two_people")]


def wired_profile(folder: Path, robot: str) -> Path:
    path = folder / f"{robot}.toml"
    path.write_text((PROFILE_DIR / f"{robot}.toml").read_text().replace(
        "[laser]\n", '[laser]\ndevice = "lms200:sim"\n', 1))
    return path


def run_wired(app: str, robot: str, scenario: str, folder: Path) -> list[dict]:
    application = find_application(app)
    loaded = load_folder(application, robot=robot)
    opened = open_robot(wired_profile(folder, robot),
                        scenario=application / "scenarios" / f"{scenario}.toml", fast=True)
    trace = TraceWriter(folder / "trace.jsonl")
    database = ApplicationDatabase(folder / "data" / f"{loaded.app.name}.sqlite",
                                   loaded.schema_file)
    try:
        assert isinstance(opened.skills.hardware.laser, LMS2xxLaser)
        Run(loaded.app, opened, dialog=loaded.dialog, trace=trace, database=database,
            echo=None).run()
    finally:
        opened.close()
        trace.close()
        database.close()
    return read_trace(folder / "trace.jsonl")


def states(trace: list[dict]) -> list[str]:
    return [e["to"] for e in trace if e["kind"] == "transition"]


@pytest.mark.slow
@pytest.mark.parametrize("robot", ["horos", "perses"])
@pytest.mark.parametrize("app, scenario", CASES)
def test_the_laser_on_its_wire_reaches_the_same_states(app_runs, tmp_path, robot, app,
                                                        scenario):
    reference = app_runs.run(app, robot, scenario)        # the in-process laser, via the CLI
    trace = run_wired(app, robot, scenario, tmp_path)
    assert len(states(reference.trace)) > 1
    assert states(trace) == states(reference.trace)
    assert not [e for e in trace if e["kind"] in ("link", "fault")]


def compare_every_scenario(robot: str) -> None:
    """`python -m tests.applications.test_wire_laser ROBOT`: every bundled scenario of the
    survey, the guide and the receptionist, in-process laser against the laser on its wire."""
    import tempfile

    from tests.applications.app_runs import AppRuns
    root = Path(tempfile.mkdtemp())
    (root / "reference").mkdir()
    runs, same, total = AppRuns(root / "reference"), 0, 0
    for app in ("survey", "guide", "receptionist"):
        scenarios = sorted(p.stem for p in (find_application(app) / "scenarios").glob("*.toml"))
        for scenario in scenarios:
            folder = root / f"{app}-{scenario}"
            folder.mkdir()
            reference = states(runs.run(app, robot, scenario).trace)
            wired = states(run_wired(app, robot, scenario, folder))
            same, total = same + (wired == reference), total + 1
            print(f"{app} {scenario}: {'same states' if wired == reference else 'DIFFERENT'}",
                  flush=True)
    print(f"{robot}: {same}/{total} scenarios reach the same states with the laser on its wire")


if __name__ == "__main__":
    import sys
    compare_every_scenario(sys.argv[1] if len(sys.argv) > 1 else "horos")
