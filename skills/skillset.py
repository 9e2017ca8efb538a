"""A robot's skills, opened together over its hardware; the one door from L2 into L1.

`sense()` is tick steps 1–2 (hardware, then skills write the blackboard); `act()` is steps 5–6
(motion through the safety arbiter to the base). Which skills exist follows the profile:
head control only with a pan-tilt unit, the questionnaire only with a touch screen, navigation
only with a map.
"""
from __future__ import annotations

from pathlib import Path

from robots.exceptions import RobotError
from robots.hardware import Hardware, open_hardware
from robots.profile import available_robots as _available_robots
from robots.profile import load_profile
from skills.blackboard import Blackboard
from skills.events import EventLog
from skills.exceptions import SkillError, SkillUnavailableError
from skills.head import HeadControl
from skills.localization import Localization
from skills.motion import Motion
from skills.navigation.gridmap import GridMap, load_map, map_from_floor
from skills.navigation.navigation import Navigation
from skills.obstacles import ObstacleSensing
from skills.perception import PeoplePerception
from skills.questionnaire import Questionnaire
from skills.skill import Skill
from skills.speech import Speech


def available_robots() -> list[str]:
    return _available_robots()


def robot_capabilities(robot: str) -> frozenset[str]:
    try:
        return load_profile(robot).capabilities
    except RobotError as exc:
        raise SkillError(str(exc)) from exc


class SkillSet:
    def __init__(self, hardware: Hardware, map: str | Path | GridMap | None = None) -> None:
        self.hardware = hardware
        self.profile = hardware.profile
        self.blackboard = Blackboard(self.profile.name)
        self.events = EventLog()
        bb, ev = self.blackboard, self.events
        self.localization = Localization(bb, ev, hardware.base)
        self.obstacles = ObstacleSensing(bb, ev, self.profile, self.localization, hardware.laser)
        user_range = self.profile.people_detector.range if self.profile.people_detector else 5.0
        self.perception = PeoplePerception(bb, ev, self.localization, hardware.people_detector,
                                           hardware.laser, user_range=user_range)
        self.motion = Motion(bb, ev, hardware.base, self.profile.limits, self.localization,
                             self.perception)
        self.speech = Speech(bb, ev, hardware.speaker) if hardware.speaker else None
        self.head = (HeadControl(bb, ev, hardware.head, self.profile.head, self.localization,
                                 self.perception) if hardware.head is not None else None)
        self.questionnaire = Questionnaire(bb, ev, hardware.screen) if hardware.screen else None
        # navigation: present when the robot has a map (in simulation: the simulated floor)
        self.map = _robot_map(hardware, map)
        self.navigation = (Navigation(bb, ev, self.map, self.profile, self.localization,
                                      self.perception, self.motion, hardware.laser)
                           if self.map is not None else None)
        self._sensing: list[Skill] = [s for s in (
            self.localization, self.obstacles, self.perception, self.speech, self.head,
            self.questionnaire, self.navigation) if s is not None]

    @property
    def name(self) -> str:
        return self.profile.name

    @property
    def capabilities(self) -> frozenset[str]:
        return self.hardware.capabilities

    def now(self) -> float:
        return self.hardware.clock.now()

    def require(self, skill: str) -> Skill:
        """The named skill, or a clear error naming the capability the robot lacks."""
        found = getattr(self, skill, None)
        if found is None:
            raise SkillUnavailableError(f"robot '{self.name}' has no {skill} skill "
                                        f"(capabilities: {', '.join(sorted(self.capabilities))})")
        return found

    def sense(self) -> float:
        now = self.hardware.sense()
        for skill in self._sensing:
            skill.sense(now)
        return now

    def act(self) -> None:
        self.motion.act(self.now())

    def wait_until(self, t: float) -> None:
        """Let robot time reach `t`: a jump on the simulated clock, a sleep on the real one."""
        self.hardware.clock.sleep_until(t)

    @property
    def simulated_time(self) -> bool:
        return self.hardware.clock.simulated

    def emergency_stop(self) -> None:
        """Zero velocity now and drop every goal (a behavior raised, or the loop is ending)."""
        now = self.now()
        self.motion.stop_now(now)
        for skill in (self.navigation, self.speech, self.head, self.questionnaire):
            if skill is not None and hasattr(skill, "cancel"):
                skill.cancel(now)

    @property
    def scenario_duration(self) -> float | None:
        return self.hardware.scenario_duration

    def ground_truth(self) -> list[tuple[str, float, float]]:
        return self.hardware.ground_truth()

    def close(self) -> None:
        try:
            self.hardware.close()
        finally:
            self.blackboard.clear()


def open_skills(robot: str | Path, *, port: str | None = None, scenario: str | Path | None = None,
                fast: bool = False, seed: int = 0, map: str | Path | None = None) -> SkillSet:
    """Open the robot's hardware (real or simulated) and its skills.

    `map` (a floor name, floor file or map_server YAML) is the map navigation uses; in
    simulation it defaults to the simulated floor, on a real robot there is none by default."""
    try:
        hardware = open_hardware(robot, port=port, scenario=scenario, fast=fast, seed=seed)
    except RobotError as exc:
        raise SkillError(str(exc)) from exc
    try:
        return SkillSet(hardware, map=map)
    except Exception:
        hardware.close()
        raise


def _robot_map(hardware: Hardware, map: str | Path | GridMap | None) -> GridMap | None:
    """The map the robot navigates in: the one given, else the simulated floor, else none."""
    if isinstance(map, GridMap):
        return map
    if map is not None:
        return load_map(map)
    simulation = hardware.simulation
    if simulation is None:
        return None
    floor = simulation.world.floor
    key = (floor.name, floor.segments.tobytes(), tuple(sorted(floor.places.items())))
    if key not in _floor_maps:        # one grid per floor: its cost map and graph are cached on it
        _floor_maps[key] = map_from_floor(floor)
    return _floor_maps[key]


_floor_maps: dict[tuple, GridMap] = {}
