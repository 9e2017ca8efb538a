"""The robot as L3 sees it: percepts in, one active macro-behavior out, events for the trace.

L3 opens a robot here (`open_robot`), which opens the skills, which open the hardware. Per
tick L3 calls `sense()` (steps 1–2, returns the percept view), maybe `activate()` (step 3's
outcome), then `act()` (steps 4–6). If a behavior raises, the robot stops at once, records a
fault, and stays stopped: nothing resumes motion until L3 opens it again.
"""
from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

from behaviors.active import ActiveBehavior
from behaviors.exceptions import BehaviorError, BehaviorFault, RobotOpenError
from behaviors.percept_view import PerceptTracker, describe
from behaviors.percepts import PerceptView
from behaviors.registry import BehaviorContext, get_behavior
from skills.exceptions import SkillError
from skills.skillset import SkillSet, open_skills

log = logging.getLogger("interbot.behaviors")


class Robot:
    def __init__(self, skills: SkillSet) -> None:
        self.skills = skills
        self.active = ActiveBehavior(skills.capabilities)
        self.percepts = PerceptTracker()
        self.fault: str | None = None
        self._events: list[dict[str, Any]] = []
        self._view: PerceptView | None = None

    @property
    def name(self) -> str:
        return self.skills.name

    @property
    def capabilities(self) -> frozenset[str]:
        return self.skills.capabilities

    @property
    def tablet_url(self) -> str | None:
        """The tablet page's address with its token (print it: it is the key), or None."""
        return self.skills.tablet_url

    @property
    def notes(self) -> list[str]:
        """What the user should know about the devices as opened (e.g. speech printed only)."""
        return self.skills.notes

    @property
    def behavior(self) -> str | None:
        return self.active.name

    @property
    def simulated_time(self) -> bool:
        return self.skills.simulated_time

    def now(self) -> float:
        return self.skills.now()

    def wait_until(self, t: float) -> None:
        self.skills.wait_until(t)

    @property
    def places(self) -> list[str] | None:
        """The place names of the robot's map (None: the robot has no map)."""
        grid = self.skills.map
        return None if grid is None else sorted(grid.places)

    @property
    def map_name(self) -> str | None:
        grid = self.skills.map
        return None if grid is None else grid.name

    def cannot_run(self, behaviors: set[str]) -> dict[str, str]:
        """Of `behaviors`, those this robot as opened cannot realize, with the reason."""
        problems = {}
        for name in sorted(behaviors):
            try:
                get_behavior(name).realization_for(self.capabilities)
            except BehaviorError as exc:
                problems[name] = str(exc)
        return problems

    def sense(self) -> PerceptView:
        now = self.skills.sense()
        self._view = self.percepts.view(self.skills, now, self.active.status)
        for failure in self.percepts.new_failures():
            self._events.append({"t": round(now, 3), "kind": "plugin", "group": "percept",
                                 "plugin": failure.plugin, "error": failure.error,
                                 "percepts": list(failure.percepts)})
        return self._view

    def start_snapshots(self, inputs: bool = True) -> None:
        """Make `snapshot()` possible from the next tick on (the hardware logs its readings);
        `inputs` adds the exact readings to each snapshot (what a recording needs for replay)."""
        self.skills.start_snapshots(inputs)

    def snapshot(self) -> dict:
        """This tick at L2 as plain data: the active behavior and its py_trees tree with each
        node's status, the percepts with values and ages, the fault if any; `skills` holds
        L1's part (which holds L0's). Call after `act()`; needs `start_snapshots()` first."""
        skills = self.skills.snapshot()
        view = self._view
        ages = {key: entry["age"] for key, entry in skills["blackboard"].items()}
        ages.update((f"skills/{name}/status", status["age"])
                    for name, status in skills["skills"].items())
        return {
            "t": skills["t"],
            "behavior": self.active.name,
            "realization": self.active.realization,
            "tree": tree_snapshot(self.active.root),
            "percepts": {} if view is None else describe(view, ages),
            "fault": self.fault,
            "skills": skills,
        }

    def top_view(self) -> dict:
        """What a top view draws: walls and places where known, the robot's outline and sonar
        poses (see `robots.hardware.Hardware.top_view`)."""
        return self.skills.top_view()

    def activate(self, behavior: str, params: dict[str, Any] | None = None) -> str:
        """Make `behavior` the active one (halting the old tree first); returns the realization."""
        if self.fault:
            raise BehaviorFault(f"robot '{self.name}' is stopped after a fault: {self.fault}")
        now = self.now()
        realization = self.active.switch(behavior, BehaviorContext(self.skills, dict(params or {})))
        self.percepts.restart(now)
        self._events.append({"t": round(now, 3), "kind": "behavior", "name": behavior,
                             "realization": realization})
        return realization

    def act(self) -> None:
        """Tick the active tree, then let the skills drive; a raising behavior stops the robot."""
        if self.fault:
            self.skills.emergency_stop()
            return
        try:
            self.active.tick()
        except Exception as exc:  # any fault in a behavior: stop, record, stay stopped
            self._fail(f"behavior '{self.active.name}' raised {type(exc).__name__}: {exc}")
            return
        self.skills.act()

    def _fail(self, reason: str) -> None:
        log.error("fault: %s", reason)
        self.fault = reason
        self.skills.emergency_stop()
        try:
            self.active.halt()
        except Exception as exc:   # a tree that cannot even halt: we are stopped anyway
            log.error("halting the faulty tree raised too: %s", exc)
            self.active.root = None
        self._events.append({"t": round(self.now(), 3), "kind": "fault", "reason": reason})

    def events(self) -> list[dict[str, Any]]:
        """Everything that happened since the last call, oldest first, as trace dicts."""
        events = self._events + [e.as_dict() for e in self.skills.events.drain()]
        self._events = []
        events.sort(key=lambda e: e["t"])
        return events

    @property
    def scenario_duration(self) -> float | None:
        """How long the simulated scenario suggests running, s (None on a real robot)."""
        return self.skills.scenario_duration

    @property
    def scenario_people(self) -> int | None:
        """How many simulated people the scenario brings (None on a real robot)."""
        return self.skills.scenario_people

    def ground_truth(self) -> list[tuple[str, float, float]]:
        return self.skills.ground_truth()

    def close(self) -> None:
        try:
            self.active.halt()
        finally:
            self.skills.close()


def tree_snapshot(node) -> dict | None:
    """A py_trees tree as nested dicts: name, py_trees class, status, feedback, children."""
    if node is None:
        return None
    out = {"name": node.name, "type": type(node).__name__, "status": node.status.value}
    if node.feedback_message:
        out["feedback"] = node.feedback_message
    children = getattr(node, "children", None)
    if children:
        out["children"] = [tree_snapshot(child) for child in children]
    return out


def open_robot(robot: str | Path, *, port: str | None = None, scenario: str | Path | None = None,
               fast: bool = False, seed: int = 0, gui: str | None = None,
               speech_wav: str | Path | None = None, language: str = "en",
               voice: str | None = None, listen: bool = False, replay=None,
               map: str | Path | None = None,
               initial_pose: tuple[float, float, float] | None = None,
               reset_faults: bool = False, devices: dict[str, str | None] | None = None,
               wire: bool = False) -> Robot:
    """Open `robot` with its skills and hardware (simulated unless `port`). `map` (a bundled
    floor name, a floor .toml or a map_server .yaml) replaces the simulated floor's map for
    localization and navigation, or gives a real base one; `initial_pose` (x m, y m, heading
    rad) is where localization starts (see `skills.skillset.open_skills`). `gui`
    ([HOST:]PORT) serves the tablet page; `speech_wav`, `language`, `voice` set speech output
    and `listen` speech input (see `skills.skillset.open_skills`, which passes them on).
    `replay` plays a recording instead of hardware: an object with `devices` (the recorded
    robot's devices) iterating over the recorded hardware inputs, tick by tick (see
    `robots.replay`). `reset_faults` clears a drive fault found at start-up, where the base
    has such a reset (refused where it has not). `devices` names devices' addresses over the
    profile's ({"laser": ..., "head": ..., "camera": ...}); `wire` puts the simulated robot's
    devices on their wires (see `robots.addresses`)."""
    try:
        skills = open_skills(robot, port=port, scenario=scenario, fast=fast, seed=seed,
                             gui=gui, speech_wav=speech_wav, language=language, voice=voice,
                             listen=listen, replay=replay, map=map,
                             initial_pose=initial_pose, reset_faults=reset_faults,
                             devices=devices, wire=wire)
    except SkillError as exc:
        raise RobotOpenError(str(exc)) from exc
    try:
        return Robot(skills)
    except BaseException:      # whatever ends the opening once the base is open closes it
        skills.close()
        raise
