"""A laser on its wire that falls silent, sends garbage or is unplugged while the robot drives:
the robot stops rather than drive blind, the trace has a `link` episode naming the laser, the
behaviors see `robot.fault`, the summary counts the laser's episode, and nothing moves again
while the laser is down. Whole runs with `--wire` (the guide navigating on HOROS, the shopping
assistant following on PERSES), the fault made in the laser's emulator at the first tick the
robot drives faster than MOVING."""
from __future__ import annotations

import numpy as np
import pytest

from applications.appfolder import load_folder
from applications.database import ApplicationDatabase
from applications.graph.loader import find_application
from applications.runtime import Run
from behaviors.robot import open_robot

MOVING = 0.15                # m/s: the robot is under way
STOPPED = 0.02               # m/s: standing
STOP_WITHIN = 1.5            # s of robot time from the fault to standing (link-down + braking)
AFTER = 6.0                  # s of robot time watched after the fault


def mute(emulator) -> None:
    emulator.muted = True


def garble(emulator) -> None:
    """Every byte the laser sends from now on is noise (no STX+address frame start)."""
    send, rng = emulator._send, np.random.default_rng(7)

    def noisy(data: bytes) -> None:
        send(bytes(rng.integers(0x03, 0x7f, len(data), dtype=np.uint8)))
    emulator._send = noisy


def unplug(emulator) -> None:
    emulator.unplug()


FAULTS = {"silent": mute, "garbage": garble, "unplugged": unplug}


class Watched(Exception):
    """Enough was seen after the fault: end the run."""


class FaultAtFirstMove:
    """A tick observer: makes the fault once the robot drives, then records the body's speed."""

    robot_snapshot = False

    def __init__(self, robot, fault) -> None:
        self.robot, self.fault = robot, fault
        self.world = robot.skills.hardware.simulation.world
        self.at: float | None = None
        self.state = ""                                  # the application's state then
        self.speeds: list[tuple[float, float]] = []      # (t, |v|) after the fault
        self.faults_seen: list[bool] = []

    def __call__(self, snapshot) -> None:
        t, speed = snapshot["t"], abs(self.world.body.v)
        if self.at is None:
            if speed > MOVING:
                self.at, self.state = t, snapshot["state"]
                self.fault(self.robot.skills.hardware.laser.emulator)
            return
        self.speeds.append((t, speed))
        # robot.fault is `not robot/link` (behaviors.percept_view)
        self.faults_seen.append(self.robot.skills.blackboard.value("robot/link") is False)
        if t > self.at + AFTER:
            raise Watched


@pytest.mark.slow
@pytest.mark.parametrize("fault", sorted(FAULTS))
@pytest.mark.parametrize("app, robot, scenario, driving", [
    ("guide", "horos", "follows", "GuideToRoom"),      # navigating
    ("shopping", "perses", "follow_me", "Follow"),      # following
])
def test_a_laser_fault_while_driving_stops_the_robot(tmp_path, app, robot, scenario, driving,
                                                     fault):
    folder = find_application(app)
    loaded = load_folder(folder, robot=robot)
    database = ApplicationDatabase(tmp_path / f"{app}.sqlite", loaded.schema_file)
    opened = open_robot(robot, scenario=folder / "scenarios" / f"{scenario}.toml", fast=True,
                        wire=True)
    watch = FaultAtFirstMove(opened, FAULTS[fault])
    run = Run(loaded.app, opened, dialog=loaded.dialog, echo=None, observers=[watch],
              database=database)
    events = []
    run.trace.write = events.append           # keep the events instead of writing a file
    try:
        with pytest.raises(Watched):
            run.run()
    finally:
        opened.close()
        database.close()
    assert watch.at is not None, "the robot never drove"
    assert watch.state == driving
    standing = [t for t, speed in watch.speeds if speed < STOPPED]
    assert standing and standing[0] - watch.at <= STOP_WITHIN, watch.speeds[:20]
    assert all(speed < STOPPED for t, speed in watch.speeds if t >= standing[0]), \
        "the robot drove again while its laser was down"
    downs = [e for e in events if e.get("kind") == "link" and e.get("state") == "down"]
    assert downs and downs[0].get("device") == "laser", downs
    assert "laser link is down" in downs[0]["reason"]
    assert any(watch.faults_seen)                      # behaviors saw robot.fault
    lines = run.summary.lines()
    assert any(line.startswith("link to the laser: down 1 time(s)") for line in lines), lines
