"""HOROS's applications with its pan-tilt head on a wire: in the simulated world the head goes
through the VISCA driver and the camera emulator (as the base goes through P2OS and its
firmware emulator), and a bundled scenario of each of the survey, the guide and the
receptionist goes through the same states at the same times, with the same behaviors and
realizations, as with the simulated head. Every scenario, with the head and every other
device on its wire at once, is test_portability's `--wire` test (whose shared in-process runs
cost nothing more); this one keeps the stricter claim (the same times) on one scenario per
application, so the suite does not make each run twice."""
from __future__ import annotations

from pathlib import Path

import pytest

import applications
from applications.appfolder import load_folder
from applications.database import ApplicationDatabase
from applications.runtime import Run
from applications.trace import TraceWriter, read_trace
from behaviors.robot import open_robot

BUNDLED = Path(applications.__file__).parent / "bundled"
SURVEY = BUNDLED / "survey"
SCENARIOS = sorted(p.stem for p in (SURVEY / "scenarios").glob("*.toml"))
CASES = [("survey", "complete"), ("guide", "follows"), ("receptionist", "visitor")]
HOROS = Path(applications.__file__).parent.parent / "robots" / "profiles" / "horos.toml"


def wired_horos(folder: Path) -> Path:
    """HOROS's profile with its head named on a serial line (the simulation emulates it)."""
    path = folder / "horos_wired.toml"
    path.write_text(HOROS.read_text().replace("[head]\n", '[head]\ndevice = "visca:/dev/ttyUSB1"\n',
                                              1))
    return path


def run_app(robot_profile, app: str, scenario: str, folder: Path) -> tuple[list[dict], str]:
    """One `interbot run APP --fast --scenario S` in process; (trace, the head's class)."""
    loaded = load_folder(BUNDLED / app)
    robot = open_robot(robot_profile, scenario=BUNDLED / app / "scenarios" / f"{scenario}.toml",
                       fast=True, seed=0)
    head = type(robot.skills.hardware.head).__name__
    trace_path = folder / f"{app}-{scenario}-{head}.jsonl"
    trace = TraceWriter(trace_path)
    database = ApplicationDatabase(folder / f"{app}-{scenario}-{head}.sqlite",
                                   loaded.schema_file)
    try:
        Run(loaded.app, robot, dialog=loaded.dialog, trace=trace, database=database,
            echo=None).run()
    finally:
        robot.close()
        trace.close()
        database.close()
    return read_trace(trace_path), head


def test_every_survey_scenario_is_covered():
    assert {"nobody", "passerby", "complete", "callback", "leave_midway", "two_people"} <= \
        set(SCENARIOS)


@pytest.mark.slow
@pytest.mark.parametrize("app, scenario", CASES)
def test_same_states_with_the_head_on_the_wire(tmp_path, app, scenario):
    reference, sim_head = run_app("horos", app, scenario, tmp_path)
    wired, wired_head = run_app(wired_horos(tmp_path), app, scenario, tmp_path)
    assert (sim_head, wired_head) == ("SimPanTilt", "ViscaHead")

    def states(trace):
        return [(e["t"], e["from"], e["to"]) for e in trace if e["kind"] == "transition"]

    def behaviors(trace):
        return [(e["name"], e["realization"]) for e in trace if e["kind"] == "behavior"]
    assert states(wired) == states(reference)
    assert behaviors(wired) == behaviors(reference)
    assert not [e for e in wired if e["kind"] in ("link", "crash", "fault")]
