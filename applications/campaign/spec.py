"""A campaign spec: which runs make the grid.

    [campaign]
    name = "attract"
    app = "app"                       # a bundled application or a folder (relative to this
                                      # file); or a list of them, each a row of the grid
    robots = ["horos"]                # default: the application's robot
    maps = []                         # --map of each run (default: the scenario's)
    scenarios = ["visitors.toml"]     # scenario families: files (relative) or the app's names
    seeds = 4                         # 0 .. 3; or a list [3, 7, 11]
    duration = 1800.0                 # s of robot time per run (default: the scenario's)
    workers = 2                       # runs at once (default: the CPUs)
    record = false                    # keep each run's recording (run.mcap)

    [learner]                         # every combination is run
    choose = ["learn", "first", "random"]   # --choose ("file", the default: the file's by=)
    learner = ["thompson"]                  # --learner
    freeze = [false]                        # --freeze
    window = [0]                            # --window (0: every episode counts)

Each run is one row of the grid; its key names the row, so a result is found again after an
interruption and never run twice.
"""
from __future__ import annotations

import itertools
import os
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

from applications.exceptions import ApplicationError

CAMPAIGN_KEYS = {"name", "app", "robots", "maps", "scenarios", "seeds", "duration", "workers",
                 "record", "sessions", "shift"}
MAX_SESSIONS = 1000         # session i of seed s runs with seed s * MAX_SESSIONS + i
LEARNER_KEYS = {"choose": ("file", "learn", "first", "random", "rotate"),
                "learner": ("thompson", "ucb"), "freeze": (False, True), "window": None}


@dataclass(frozen=True)
class RunSpec:
    """One run of the grid: the `interbot run` arguments that make it."""
    app: str
    robot: str | None
    map: str | None
    scenario: str
    seed: int
    choose: str | None
    learner: str
    freeze: bool
    window: int = 0
    duration: float | None = None
    record: bool = False
    session: int = 0                # its place in a chain of sessions (0: the first)
    sessions: int = 1               # the chain's length (1: a run on its own)
    shift_at: int = 0               # from this session on (0: never) the world changes to
    shift_scenario: str | None = None   # this scenario
    shift_app: str | None = None        # and this application (None: the same)

    @property
    def key(self) -> str:
        return (f"app={Path(self.app).name},robot={self.robot or '-'},map={self.map or '-'},"
                f"scenario={Path(self.scenario).stem},seed={self.seed},"
                f"choose={self.choose or '-'},learner={self.learner},freeze={int(self.freeze)}"
                + (f",window={self.window}" if self.window else "")
                + (f",shift={Path(self.shift_scenario or self.scenario).stem}@{self.shift_at}"
                   if self.shift_at else "")
                + (f",session={self.session}" if self.sessions > 1 else ""))

    @property
    def group(self) -> str:
        """The run's row of the summary: everything but the seed (and the session)."""
        key = self.key.replace(f",seed={self.seed},", ",")
        return key.replace(f",session={self.session}", "") if self.sessions > 1 else key

    @property
    def folder_name(self) -> str:
        """The run's folder under the campaign's `runs/`."""
        return "".join(c if c.isalnum() or c in "=-_." else "_" for c in self.key)

    @property
    def previous(self) -> "RunSpec | None":
        """The session before this one in its chain (whose statistics it starts from)."""
        return replace(self, session=self.session - 1) if self.session > 0 else None

    @property
    def shifted(self) -> bool:
        return bool(self.shift_at) and self.session >= self.shift_at

    @property
    def run_seed(self) -> int:
        return self.seed * MAX_SESSIONS + self.session if self.sessions > 1 else self.seed

    def argv(self, folder: Path) -> list[str]:
        """The `interbot run` arguments, writing into the run's `folder`."""
        app = (self.shift_app or self.app) if self.shifted else self.app
        scenario = (self.shift_scenario or self.scenario) if self.shifted else self.scenario
        argv = ["run", app, "--fast", "--quiet", "--scenario", scenario,
                "--seed", str(self.run_seed), "--learner", self.learner,
                "--data", str(folder), "--trace", str(folder / "trace.jsonl")]
        for flag, value in (("--robot", self.robot), ("--map", self.map),
                            ("--choose", self.choose)):
            if value is not None:
                argv += [flag, value]
        if self.duration is not None:
            argv += ["--duration", f"{self.duration:g}"]
        if self.freeze:
            argv.append("--freeze")
        if self.window:
            argv += ["--window", str(self.window)]
        if self.record:
            argv += ["--record", str(folder / "run.mcap")]
        return argv


@dataclass(frozen=True)
class Campaign:
    name: str
    path: Path
    runs: tuple[RunSpec, ...]
    workers: int = field(default=2)


def load_campaign(path: str | Path) -> Campaign:
    """Read and check a spec; ApplicationError naming the file and the field when wrong."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ApplicationError(f"{path}: no such campaign spec") from None
    except tomllib.TOMLDecodeError as exc:
        raise ApplicationError(f"{path}: not valid TOML: {exc}") from None
    return _Reader(path).campaign(data)


class _Reader:
    def __init__(self, path: Path) -> None:
        self.path = path

    def fail(self, field_name: str, why: str) -> ApplicationError:
        return ApplicationError(f"{self.path}: {field_name}: {why}")

    def campaign(self, data: dict) -> Campaign:
        unknown = set(data) - {"campaign", "learner"}
        if unknown:
            raise self.fail(sorted(unknown)[0], "unknown table; allowed: [campaign], [learner]")
        head, learner = data.get("campaign", {}), data.get("learner", {})
        self.known(head, "campaign", CAMPAIGN_KEYS)
        self.known(learner, "learner", set(LEARNER_KEYS))
        if "app" not in head:
            raise self.fail("campaign.app", "is missing: a bundled application's name or a "
                            "folder (relative to this file)")
        apps = [self.app(a) for a in (head["app"] if isinstance(head["app"], list)
                                      else [head["app"]])]
        robots = self.strings(head, "robots", [None])
        maps = [self.relative(m) for m in self.strings(head, "maps", [None])]
        scenarios = [self.scenario(s) for s in self.strings(head, "scenarios", None)]
        seeds = self.seeds(head.get("seeds", 1))
        duration = head.get("duration")
        if duration is not None and (not isinstance(duration, (int, float))
                                     or isinstance(duration, bool) or duration <= 0):
            raise self.fail("campaign.duration", f"= {duration!r} must be a positive number of "
                            "seconds")
        record = head.get("record", False)
        if not isinstance(record, bool):
            raise self.fail("campaign.record", f"= {record!r} must be true or false")
        workers = head.get("workers", os.cpu_count() or 1)
        if not isinstance(workers, int) or isinstance(workers, bool) or workers < 1:
            raise self.fail("campaign.workers", f"= {workers!r} must be a whole number >= 1")
        grid = {name: self.choices(learner, name) for name in LEARNER_KEYS}
        sessions = head.get("sessions", 1)
        if (not isinstance(sessions, int) or isinstance(sessions, bool)
                or not 1 <= sessions <= MAX_SESSIONS):
            raise self.fail("campaign.sessions", f"= {sessions!r} must be a whole number "
                            f"1 .. {MAX_SESSIONS}")
        shift = self.shift(head.get("shift"), sessions)
        runs = tuple(
            RunSpec(app, robot, map_, scenario, seed, None if choose == "file" else choose,
                    method, freeze, window,
                    float(duration) if duration is not None else None, record,
                    session, sessions, *shift)
            for app, robot, map_, scenario, choose, method, freeze, window, seed, session
            in itertools.product(apps, robots, maps, scenarios, grid["choose"], grid["learner"],
                                 grid["freeze"], grid["window"], seeds, range(sessions)))
        return Campaign(str(head.get("name", self.path.stem)), self.path, runs, workers)

    def shift(self, table, sessions: int) -> tuple[int, str | None, str | None]:
        """(session, scenario, app) of `shift = { session = N, scenario = "...", app = "..." }`."""
        if table is None:
            return 0, None, None
        self.known(table, "campaign.shift", {"session", "scenario", "app"})
        at = table.get("session")
        if not isinstance(at, int) or isinstance(at, bool) or not 1 <= at < sessions:
            raise self.fail("campaign.shift.session", f"= {at!r} must be a session "
                            f"1 .. {sessions - 1} (campaign.sessions = {sessions})")
        scenario = table.get("scenario")
        if scenario is not None and not (isinstance(scenario, str) and scenario):
            raise self.fail("campaign.shift.scenario", f"= {scenario!r} must be a scenario")
        app = table.get("app")
        if scenario is None and app is None:
            raise self.fail("campaign.shift", "says nothing changes: give a scenario, an app "
                            "or both")
        return (at, self.scenario(scenario) if scenario else None,
                self.app(app) if app is not None else None)

    def known(self, table, name: str, allowed: set[str]) -> None:
        if not isinstance(table, dict):
            raise self.fail(name, "must be a table")
        for key in table:
            if key not in allowed:
                raise self.fail(f"{name}.{key}", f"unknown field; allowed: {', '.join(sorted(allowed))}")

    def strings(self, table: dict, key: str, default):
        value = table.get(key, default)
        if value is None:
            raise self.fail(f"campaign.{key}", "is missing: a list of names or files")
        if isinstance(value, str):
            value = [value]
        if not (isinstance(value, list) and value and all(isinstance(v, str) or v is None
                                                           for v in value)):
            raise self.fail(f"campaign.{key}", f"= {value!r} must be a non-empty list of strings")
        return value

    def relative(self, value: str | None) -> str | None:
        """A file relative to the spec when it exists there; else the name as written."""
        if value is None:
            return None
        candidate = self.path.parent / value
        return str(candidate.resolve()) if candidate.exists() else value

    def app(self, value) -> str:
        if not isinstance(value, str) or not value:
            raise self.fail("campaign.app", f"= {value!r} must be an application's name or folder")
        return self.relative(value)

    def scenario(self, value: str) -> str:
        return self.relative(value)

    def seeds(self, value) -> list[int]:
        if isinstance(value, int) and not isinstance(value, bool) and value >= 1:
            return list(range(value))
        if (isinstance(value, list) and value and all(isinstance(v, int) and not isinstance(v, bool)
                                                      and v >= 0 for v in value)):
            return list(value)
        raise self.fail("campaign.seeds", f"= {value!r} must be a count (>= 1) or a list of "
                        "seeds (whole numbers >= 0)")

    def choices(self, table: dict, key: str) -> list:
        allowed = LEARNER_KEYS[key]
        if allowed is None:                       # window: whole numbers >= 0
            value = table.get(key, [0])
            value = value if isinstance(value, list) else [value]
            if not value or not all(isinstance(v, int) and not isinstance(v, bool) and v >= 0
                                    for v in value):
                raise self.fail(f"learner.{key}", f"= {value!r} must be whole numbers >= 0 "
                                "(0: every episode counts)")
            return value
        value = table.get(key, [allowed[0]])
        if not isinstance(value, list):
            value = [value]
        for item in value:
            if item not in allowed:
                shown = ", ".join(repr(a) for a in allowed)
                raise self.fail(f"learner.{key}", f"{item!r} is not one of {shown}")
        if not value:
            raise self.fail(f"learner.{key}", "is empty")
        return value
