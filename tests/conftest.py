"""Shared test set-up."""
from __future__ import annotations

import gc
import os

import pytest

WORKERS_PER_CORE = 2


def pytest_xdist_auto_num_workers(config):
    """`-n auto`: two workers per core. A third of a worker's time is spent waiting in real
    time (drivers' timeouts, links going silent, a browser), which a second worker's computing
    fills: on 2 cores the suite took 7 min 12 s with 4 workers against 9 min with 2."""
    return WORKERS_PER_CORE * (os.cpu_count() or 1)


@pytest.hookimpl(wrapper=True)
def pytest_collection(session):
    """Collect the tests without the cyclic collector, then take what they imported out of its
    reach (gc.freeze) and collect as before. Importing every test module makes ~190 000 objects
    that never become garbage; the collector walked them again and again as they came (a
    worker's collection: 6.8 s, 5.2 s without), and every full collection during the tests
    walked them once more: about 0.2 s on one quiet core (benchmarks/suite_gc.py), 0.3-0.7 s in
    a loaded worker, several times a run, stalling every thread of the process at once. A
    real-time test whose driver gives a device 0.3 s to answer (tests/faults) then saw the
    device 'silent'. Only pauses go: what the tests create is collected as before."""
    gc.disable()
    try:
        return (yield)
    finally:
        gc.collect()
        gc.freeze()
        gc.enable()


STANDING_PERSON = """
[scenario]
name = "standing"
duration = 60.0
robot = {robot}
motion = "{motion}"
[[person]]
id = "sam"
appear = 0.0
at = [{x}, {y}]
speed = 1.0
steps = [ {{ pause = 100.0 }} ]
"""


@pytest.fixture(scope="session", autouse=True)
def tablet_pairing_secret(tmp_path_factory):
    """The tablet page's pairing secret (robots.tablet.pairing) in the session's temporary
    folder, never in the home folder of whoever runs the tests (runs started as subprocesses
    inherit it)."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("INTERBOT_TABLET_SECRET",
                     str(tmp_path_factory.mktemp("tablet") / "tablet-secret"))
        yield


@pytest.fixture
def standing_person(tmp_path):
    """A scenario file with one person standing at (x, y) from the start (robot at robot_home,
    or at `robot` = (x, y, heading in degrees)); `motion="scripted"`: exactly there, whatever
    the robot does (social: they step aside)."""
    def write(x: float, y: float, motion: str = "social", robot=None):
        pose = "home" if robot is None else "_".join(f"{float(v):g}" for v in robot)
        where = '"robot_home"' if robot is None else str([float(v) for v in robot])
        path = tmp_path / f"standing_{x}_{y}_{motion}_{pose}.toml"
        path.write_text(STANDING_PERSON.format(x=x, y=y, motion=motion, robot=where))
        return path
    return write


@pytest.fixture(scope="session")
def app_runs(tmp_path_factory):
    """Bundled-application runs made once per test session, shared by the pytest-xdist
    workers through the session's own temporary folder (tests/applications/app_runs.py)."""
    from tests.applications.app_runs import AppRuns
    base = tmp_path_factory.getbasetemp()
    worker = os.environ.get("PYTEST_XDIST_WORKER")            # xdist: a folder per worker …
    shared = base.parent if worker else base                   # … in the session's folder
    folder = shared / "app-runs"
    folder.mkdir(exist_ok=True)
    return AppRuns(folder)
