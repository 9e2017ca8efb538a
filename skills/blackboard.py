"""The shared memory of a robot: the py_trees blackboard, with a documented key schema.

Every key has one type, one unit and exactly one skill that writes it; every entry carries the
robot time it was written (`Stamped`), so a reader can tell fresh from stale. Each robot opened
in a process gets its own namespace, so two robots (or two tests) never share entries.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

import py_trees

from skills.exceptions import BlackboardError


@dataclass(frozen=True)
class Stamped:
    value: Any
    t: float          # robot time of the write, s

    def age(self, now: float) -> float:
        return now - self.t


@dataclass(frozen=True)
class KeySpec:
    key: str
    type: str
    unit: str
    writer: str       # the one skill that writes this key
    doc: str


def _key(key: str, type_: str, unit: str, writer: str, doc: str) -> KeySpec:
    return KeySpec(key, type_, unit, writer, doc)


SCHEMA: dict[str, KeySpec] = {spec.key: spec for spec in (
    _key("robot/pose", "tuple[float, float, float]", "m, m, rad", "localization",
         "pose estimate (x, y, heading) in the map frame (odometry alone without a map)"),
    _key("robot/velocity", "tuple[float, float]", "m/s, rad/s", "localization",
         "measured translational and rotational velocity"),
    _key("robot/link", "bool", "-", "localization",
         "the base link is up and its state is fresh (and a wired laser's link is up)"),
    # -- localization (skills.localization, skills.navigation.mcl) --
    _key("robot/odometry", "tuple[float, float, float]", "m, m, rad", "localization",
         "the base's odometry pose (x, y, heading) in its own frame; drifts"),
    _key("localization/covariance", "tuple[tuple[float, float, float], ...]",
         "m², m·rad, rad² (3×3: x, y, heading)", "localization",
         "covariance of the pose estimate (absent in odometry mode)"),
    _key("localization/lost", "bool", "-", "localization",
         "the scan no longer fits the map at the estimate, or the particles are spread wide"),
    _key("localization/fit", "float", "0..1", "localization",
         "share of the used beams whose end point lies near a wall from the estimate"),
    _key("localization/mode", "str", "-", "localization",
         "'laser', 'sonar' or 'odometry' (no map, or no range sensor)"),
    # -- end localization --
    _key("sensors/sonar", "tuple[float, ...]", "m", "obstacles",
         "last range per sonar index; inf when no echo"),
    _key("obstacles/front", "float", "m", "obstacles",
         "free distance ahead of the body (sonar and laser), inf when clear"),
    _key("obstacles/rear", "float", "m", "obstacles",
         "free distance behind the body (rear sonars), inf when clear, 0 without rear sonars"),
    _key("obstacles/turn_room", "tuple[float, float]", "rad", "obstacles",
         "how far the body may turn left, right on the spot before a corner nears a reading; "
         "inf for a round body"),
    _key("people/tracks", "tuple[Track, ...]", "m, m/s (world frame)", "perception",
         "confirmed people tracks"),
    _key("people/user", "Track | None", "m, m/s (world frame)", "perception",
         "the selected interaction partner"),
    _key("people/user_distance", "float | None", "m", "perception",
         "distance from the robot centre to the user"),
    _key("people/user_approach", "float | None", "m/s", "perception",
         "speed of the user towards the robot (negative: moving away)"),
    _key("head/pan_tilt", "tuple[float, float]", "rad, rad", "head", "current pan and tilt"),
    _key("speech/busy", "bool", "-", "speech", "an utterance is being spoken"),
    _key("speech/last", "str", "-", "speech", "the last utterance started"),
    _key("survey/progress", "SurveyProgress", "-", "questionnaire",
         "answers given so far and whether every question has one"),
    _key("motion/command", "tuple[float, float]", "m/s, rad/s", "motion",
         "the command sent to the base after the safety arbiter"),
    _key("motion/limit", "str", "-", "motion", "why the last command was capped ('' if not)"),
    # navigation (skills.navigation.navigation)
    _key("navigation/state", "NavigationState", "m, s (fields)", "navigation",
         "phase, goal, distance_left, blocked_for, blocker, replans, failure and reason"),
    _key("navigation/path", "tuple[tuple[float, float], ...]", "m (map frame)", "navigation",
         "waypoints of the current global path, start to goal"),
    # following a customer (skills.following)
    _key("following/state", "FollowState", "m, s (fields)", "following",
         "phase, target track, distance, setpoint, lost_for, predicted and last seen place, "
         "losses, reacquisitions, calls and reason"),
    # guiding (skills.guiding)
    _key("guide/state", "GuideState", "m, rad, s (fields)", "guide",
         "phase, place, the follower's distance, bearing and source, unseen_for, waiting_for, "
         "outcome and reason"),
)}

SKILL_STATUS_PREFIX = "skills/"      # skills/<name>/status: SkillStatus, written by skill <name>

_instances = itertools.count(1)


class Blackboard:
    """One robot's blackboard: writers are py_trees clients restricted to their own keys."""

    def __init__(self, robot_name: str) -> None:
        self.namespace = f"/interbot/{robot_name}{next(_instances)}"
        self._reader = py_trees.blackboard.Client(name="reader", namespace=self.namespace)
        self._readable: set[str] = set()
        for key in SCHEMA:
            self._allow_read(key)

    def _allow_read(self, key: str) -> None:
        self._reader.register_key(key=key, access=py_trees.common.Access.READ)
        self._readable.add(key)

    def _path(self, key: str) -> str:
        return f"{self.namespace}/{key}"

    def writer(self, skill: str) -> "KeyWriter":
        """A writer for `skill`, allowed to write the schema keys it owns and its status."""
        owned = [k for k, spec in SCHEMA.items() if spec.writer == skill]
        owned.append(f"{SKILL_STATUS_PREFIX}{skill}/status")
        client = py_trees.blackboard.Client(name=skill, namespace=self.namespace)
        for key in owned:
            client.register_key(key=key, access=py_trees.common.Access.WRITE)
        self._allow_read(owned[-1])
        return KeyWriter(skill, client, {key: self._path(key) for key in owned})

    def read(self, key: str) -> Stamped | None:
        """The stamped entry, or None when it was never written."""
        if key not in self._readable:
            if key in SCHEMA or key.startswith(SKILL_STATUS_PREFIX):
                return None   # a skill this robot does not have
            raise BlackboardError(f"'{key}' is not a blackboard key; see skills.blackboard.SCHEMA")
        if py_trees.blackboard.Blackboard.activity_stream is None:    # the fast path, below
            return py_trees.blackboard.Blackboard.storage.get(self._path(key))
        try:
            return self._reader.get(key)
        except KeyError:
            return None

    def entries(self) -> dict[str, Stamped]:
        """Every entry written so far, by key: one pass over the storage, for snapshots (a
        py_trees client `get` per key costs ten times more)."""
        storage = py_trees.blackboard.Blackboard.storage
        return {key: storage[self._path(key)] for key in self._readable
                if self._path(key) in storage}

    def value(self, key: str, default: Any = None, now: float | None = None,
              max_age: float | None = None) -> Any:
        """The value, or `default` when missing or older than `max_age` at `now`."""
        entry = self.read(key)
        if entry is None:
            return default
        if max_age is not None and now is not None and entry.age(now) > max_age:
            return default
        return entry.value

    def clear(self) -> None:
        """Forget this robot's entries (on close)."""
        storage = py_trees.blackboard.Blackboard.storage
        for path in [p for p in storage if p.startswith(self.namespace + "/")]:
            del storage[path]


class KeyWriter:
    """One skill's writes. The keys it may write were registered with py_trees; the write
    itself goes straight into py_trees' storage, past the client's checks (done here already)
    and its activity stream. That is a tenth of a client `set`, and a tick writes some twenty
    entries. With py_trees' activity stream on (a debugging tool), writes go through the
    client, so the stream sees them; reads (`Blackboard.read`) do the same."""

    __slots__ = ("skill", "_client", "_paths")

    def __init__(self, skill: str, client, paths: dict[str, str]) -> None:
        self.skill = skill
        self._client = client
        self._paths = paths          # key -> its absolute name in py_trees' storage

    def write(self, key: str, value: Any, t: float) -> None:
        path = self._paths.get(key)
        if path is None:
            owner = SCHEMA[key].writer if key in SCHEMA else "nobody (not in the schema)"
            raise BlackboardError(f"skill '{self.skill}' may not write '{key}'; its writer is {owner}")
        if py_trees.blackboard.Blackboard.activity_stream is None:
            py_trees.blackboard.Blackboard.storage[path] = Stamped(value, t)
        else:
            self._client.set(key, Stamped(value, t))
