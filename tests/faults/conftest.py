"""Fixtures for the fault-injection suite: a scripted robot end and `interbot run --port` on it.

The application is base-only (the survey is refused on a real port: the touch screen has no
driver yet) and shows the behaviors' side of a fault: it leaves `Wait` for `Halted` while
`robot.fault` holds and comes back once the link is fresh again.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.faults.peer import ScriptedPioneer
from tests.processes import faulthandler_env, finish

WATCH_FAULTS_APP = """<application name="watch" initial="Wait" robot="horos">
  <state name="Wait" behavior="Idle">
    <transition to="Halted" when="robot.fault"/>
  </state>
  <state name="Halted" behavior="Idle">
    <transition to="Wait" when="not robot.fault and time_in_state > 0.3s"/>
  </state>
</application>
"""
REPO = Path(__file__).resolve().parents[2]


@pytest.fixture
def peer():
    robot_end = ScriptedPioneer()
    yield robot_end
    robot_end.shutdown()


@pytest.fixture
def watch_app(tmp_path) -> Path:
    folder = tmp_path / "watch"
    folder.mkdir()
    (folder / "graph.xml").write_text(WATCH_FAULTS_APP)
    return folder


@dataclass
class Finished:
    code: int
    out: str
    err: str
    trace: list[dict]


class RunningInterbot:
    """`interbot run APP --port URL` as a separate process (signals reach it as they would)."""

    def __init__(self, app: Path, url: str, tmp_path: Path, duration: float,
                 robot: str = "horos", extra: tuple[str, ...] = ()) -> None:
        self.trace_path = tmp_path / "trace.jsonl"
        env = faulthandler_env(dict(os.environ, PYTHONPATH=str(REPO)))    # a hang shows where
        self.process = subprocess.Popen(
            [sys.executable, "-m", "applications.cli", "run", str(app), "--robot", robot,
             "--port", url, "--duration", str(duration), "--trace", str(self.trace_path),
             "--data", str(tmp_path / "data"), *extra],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=REPO, env=env)

    def finish(self, timeout: float = 60.0) -> Finished:
        out, err = finish(self.process, timeout)
        trace = []
        if self.trace_path.exists():
            trace = [json.loads(line) for line in self.trace_path.read_text().splitlines()
                     if line.strip()]
        return Finished(self.process.returncode, out, err, trace)

    def kill(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait(timeout=10)


@pytest.fixture
def start_run(tmp_path, watch_app):
    started = []

    def start(peer: ScriptedPioneer, duration: float, extra: tuple[str, ...] = ()) -> RunningInterbot:
        run = RunningInterbot(watch_app, peer.url, tmp_path, duration, extra=extra)
        started.append(run)
        assert peer.wait_open(timeout=20), "interbot never opened the scripted robot"
        return run
    yield start
    for run in started:
        run.kill()


@pytest.fixture
def start_run_on(tmp_path, watch_app):
    """`interbot run` of the watch application with `robot` on any `url`."""
    started = []

    def start(url: str, robot: str, duration: float, extra: tuple[str, ...] = ()) -> RunningInterbot:
        run = RunningInterbot(watch_app, url, tmp_path, duration, robot=robot, extra=extra)
        started.append(run)
        return run
    yield start
    for run in started:
        run.kill()


def first_stop_after(peer: ScriptedPioneer, t: float, conn: int | None = None):
    """The first VEL 0 the robot end received at or after `t` (on connection `conn`), or None."""
    for received in list(peer.received):
        if received.t >= t and (conn is None or received.conn == conn) and received.name == "VEL 0":
            return received
    return None


def commands_after_open(peer: ScriptedPioneer, conn: int) -> list[str]:
    """What connection `conn` sent after its OPEN, in order."""
    names = [r.name for r in list(peer.received) if r.conn == conn]
    return names[names.index("OPEN") + 1:] if "OPEN" in names else []


def record_delay(kind: str, delay: float) -> None:
    """Keep the fault-to-stop delay for the report (not asserted: no timed assertions)."""
    path = os.environ.get("INTERBOT_FAULT_DELAYS")
    if path:
        with open(path, "a", encoding="utf-8") as f:
            f.write(json.dumps({"fault": kind, "delay_s": round(delay, 4),
                                "load": os.getloadavg()[0]}) + "\n")
    print(f"{kind}: stop {delay * 1000:.0f} ms after the fault")


def wait(seconds: float) -> None:
    time.sleep(seconds)


def argos_drives_in_real_time():
    """ARGOS's two emulated CiA 402 drives on a virtual CAN bus, stepping the simulated world
    on the real clock: (profile, clock, emulator). The caller opens a driver on
    `virtual:{emulator.channel}` (or the emulator's socketcand server) and closes both."""
    from robots.canopen.emulator import CanOpenEmulator
    from robots.clock import RealClock
    from robots.profile import load_profile
    from robots.sim.simulation import Simulation
    argos = load_profile("argos")
    clock = RealClock()
    simulation = Simulation(argos, None, 0, clock)
    emulator = CanOpenEmulator.for_profile(argos, simulation.world, clock=clock)
    emulator.attach(simulation)
    emulator.start_clock(simulation)
    return argos, clock, emulator
