"""The paper's portability claim: the same application (the same graph.xml) runs on HOROS
(Pioneer, P2OS), PERSES (B21r, rFLEX) and ARGOS (two CiA 402 drives on CAN) with only the
robot-specific layers changed, and goes through the same states on every bundled scenario.
And the whole robot on its wires (`run --wire`: HOROS's base, laser, head, tablet and voice,
PERSES's base, laser, tablet and voice, each through its driver, protocol and emulator) goes
through the same states as the in-process simulation.

Each run is the real command line in --fast mode; each driver talks its wire protocol to its
emulator (P2OS and rFLEX over a pty, CANopen over python-can's virtual bus). Behaviors may be
realized differently (FaceUser turns the pan-tilt head on HOROS and the whole body on the
others); the sequence of states must not differ. A bundled application joins with one line in
APPLICATIONS, a base with one line in ROBOTS.
"""
from __future__ import annotations

from pathlib import Path

import pytest

import applications

BUNDLED = Path(applications.__file__).parent / "bundled"
SURVEY = BUNDLED / "survey"
SCENARIOS = sorted(p.stem for p in (SURVEY / "scenarios").glob("*.toml"))
APPLICATIONS = [        # one line per bundled application that must run unchanged on every base
    "survey",
    "guide",
    "receptionist",
]
ROBOTS = ("horos", "perses", "argos")     # P2OS, rFLEX, CANopen; the first is the reference
WIRED = ("horos", "perses")               # the paper's robots, every device on its wire
# Scenarios whose outcome on the wires differs from the in-process run, and why. Strict: a fix
# turns the case into a failure that asks for its line here to go.
# (app, scenario, robot) that reach other states on their wires, with why; none since the
# doors work (issue 22): guide/walks_away on HOROS used to stand 'blocked' beside a wall on its
# way home after the wired laser's own random stream made it stop guiding at another spot
DIVERGES: dict[tuple[str, str, str], str] = {}
CASES = [(app, scenario) for app in APPLICATIONS
         for scenario in sorted(p.stem for p in (BUNDLED / app / "scenarios").glob("*.toml"))]




def states(trace: list[dict]) -> list[str]:
    return [e["to"] for e in trace if e["kind"] == "transition"]


def realizations(trace: list[dict]) -> set[tuple[str, str]]:
    return {(e["name"], e["realization"]) for e in trace if e["kind"] == "behavior"}


def test_every_bundled_scenario_is_covered():
    assert {"nobody", "passerby", "complete", "callback", "leave_midway", "two_people"} <= set(SCENARIOS)


@pytest.mark.slow
@pytest.mark.parametrize("app, scenario", CASES)
def test_same_states_on_every_base(app_runs, app, scenario):
    # the runs are shared with the applications' own end-to-end tests (tests/applications/
    # app_runs.py): the same command line, made once
    runs = {robot: app_runs.run(app, robot, scenario) for robot in ROBOTS}
    assert all(run.code == 0 for run in runs.values()), {r: run.code for r, run in runs.items()}
    traces = {robot: run.trace for robot, run in runs.items()}
    reference = traces[ROBOTS[0]]
    assert len(states(reference)) >= 1
    for robot, trace in traces.items():
        assert states(trace) == states(reference), robot
        # The same behaviors were asked for; where one moved something, the robots differ in how.
        assert {name for name, _ in realizations(trace)} == {name for name, _ in realizations(reference)}
        if robot != ROBOTS[0] and {name for name, how in realizations(trace) if how == "body"}:
            assert realizations(trace) != realizations(reference), robot


def test_on_its_wires_every_device_goes_through_its_driver_and_emulator(tmp_path):
    from behaviors.robot import open_robot
    from robots.audio.wired import WiredVoice
    from robots.lms2xx.driver import LMS2xxLaser
    from robots.tablet.simulated import WiredTouchScreen
    from robots.visca.driver import ViscaHead

    robot = open_robot("horos", scenario=SURVEY / "scenarios" / "complete.toml", fast=True,
                       wire=True)
    try:
        hardware = robot.skills.hardware
        assert type(hardware.base).__module__.startswith("robots.p2os")
        assert (type(hardware.laser), type(hardware.head), type(hardware.screen),
                type(hardware.speaker)) == (LMS2xxLaser, ViscaHead, WiredTouchScreen,
                                            WiredVoice)
    finally:
        robot.close()


WIRED_CASES = [pytest.param(app, scenario, robot, marks=(
                   [pytest.mark.xfail(reason=DIVERGES[(app, scenario, robot)], strict=True)]
                   if (app, scenario, robot) in DIVERGES else []))
               for robot in WIRED for app, scenario in CASES]


@pytest.mark.slow
@pytest.mark.parametrize("app, scenario, robot", WIRED_CASES)
def test_the_whole_robot_on_its_wires_reaches_the_same_states(app_runs, app, scenario, robot):
    reference = app_runs.run(app, robot, scenario)           # shared with the tests above
    wired = app_runs.run(app, robot, scenario, wire=True)
    assert (reference.code, wired.code) == (0, 0)
    assert len(states(reference.trace)) >= 1
    assert states(wired.trace) == states(reference.trace)
    assert realizations(wired.trace) == realizations(reference.trace)
    assert not [e for e in wired.trace if e["kind"] in ("link", "fault", "crash")]
    answers = [e for e in wired.trace if e["kind"] == "answer"]
    assert all(e["source"] == "touch" for e in answers)      # pressed through the tablet page
