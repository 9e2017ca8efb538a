"""A robot's skills, opened together over its hardware; the one door from L2 into L1.

`sense()` is tick steps 1–2 (hardware, then skills write the blackboard); `act()` is steps 5–6
(motion through the safety arbiter to the base). Which skills exist follows the profile:
head control only with a pan-tilt unit, the questionnaire only with a touch screen, navigation
only with a map.
"""
from __future__ import annotations

import logging

import math
from pathlib import Path

import numpy as np

from robots.exceptions import RobotError
from robots.hardware import Hardware, open_hardware
from robots.profile import available_robots as _available_robots
from robots.profile import is_profile_file, load_profile
from skills.blackboard import SKILL_STATUS_PREFIX, Blackboard
from skills.events import EventLog
from skills.exceptions import SkillError, SkillUnavailableError
from skills.following import Following
from skills.guiding import Guiding
from skills.head import HeadControl
from skills.localization import Localization
from skills.motion import Motion
from skills.navigation.gridmap import GridMap, load_map, map_from_floor
from skills.navigation.mcl import MCLParams
from skills.navigation.navigation import Navigation
from skills.obstacles import ObstacleSensing
from skills.perception import PeoplePerception
from skills.people.track import Track
from skills.questionnaire import Questionnaire, SurveyProgress
from skills.skill import Skill
from skills.speech import Speech
from skills.status import SkillStatus


def available_robots() -> list[str]:
    return _available_robots()


def is_robot_file(robot: str) -> bool:
    """A robot given as a profile file (`./my_robot.toml`) rather than a bundled name."""
    return is_profile_file(robot)


def robot_capabilities(robot: str) -> frozenset[str]:
    try:
        return load_profile(robot).capabilities
    except RobotError as exc:
        raise SkillError(str(exc)) from exc


def check_device_addresses(robot: str | Path, devices: dict[str, str | None], *,
                           wire: bool = False, simulated: bool = True) -> None:
    """Refuse devices' addresses given on the command line that would not open (a SkillError
    saying which and what is allowed), before anything is opened (robots.addresses)."""
    from robots.hardware import check_addresses
    try:
        check_addresses(robot, devices, wire, simulated)
    except RobotError as exc:
        raise SkillError(str(exc)) from exc


def check_robot_devices(robot: str | Path, port: str | None = None) -> list[dict]:
    """Which of the robot's devices answer (robots.check), as plain data."""
    from robots.check import check_devices
    try:
        return [vars(check) for check in check_devices(robot, port)]
    except RobotError as exc:
        raise SkillError(str(exc)) from exc


class SkillSet:
    def __init__(self, hardware: Hardware, *, map: str | Path | GridMap | None = None,
                 initial_pose: tuple[float, float, float] | None = None, seed: int = 0) -> None:
        self.hardware = hardware
        self.profile = hardware.profile
        self.blackboard = Blackboard(self.profile.name)
        self.events = EventLog()
        bb, ev = self.blackboard, self.events
        self.map = _robot_map(hardware, map)
        if initial_pose is not None:
            initial_pose = check_initial_pose(initial_pose, self.map)
        self.localization = _localization(bb, ev, hardware, self.map, initial_pose, seed,
                                          own_floor=_is_floor_map(hardware, self.map))
        self.obstacles = ObstacleSensing(bb, ev, self.profile, self.localization, hardware.laser)
        user_range = self.profile.people_detector.range if self.profile.people_detector else 5.0
        self.perception = PeoplePerception(bb, ev, self.localization, hardware.people_detector,
                                           hardware.laser, user_range=user_range,
                                           grid=_map_for_people(hardware, self.map))
        self.motion = Motion(bb, ev, hardware.base, self.profile.limits, self.localization,
                             self.perception, footprint=self.obstacles.footprint)
        self.speech = (Speech(bb, ev, hardware.speaker, hardware.screen)
                       if hardware.speaker else None)
        self.head = (HeadControl(bb, ev, hardware.head, self.profile.head, self.localization,
                                 self.perception) if hardware.head is not None else None)
        self.questionnaire = (Questionnaire(bb, ev, hardware.screen, hardware.recognizer)
                              if hardware.screen else None)
        # navigation: present when the robot has a map (in simulation: the simulated floor)
        self.navigation = (Navigation(bb, ev, self.map, self.profile, self.localization,
                                      self.perception, self.motion, hardware.laser)
                           if self.map is not None else None)
        # guiding: watching the person who follows (needs the map to tell people from walls)
        self.guide = (Guiding(bb, ev, self.localization, self.perception, self.map,
                              self.profile.sonar, reach=user_range,
                              camera_fov=_camera_fov(self.profile))
                      if self.map is not None else None)
        # following a customer: over tracking, and navigation where there is a map
        self.following = Following(bb, ev, self.localization, self.perception, self.motion,
                                   self.navigation, self.speech)
        # following decides after perception and before navigation collects its readings
        self._sensing: list[Skill] = [s for s in (
            self.localization, self.obstacles, self.perception, self.guide, self.speech,
            self.head, self.questionnaire, self.following, self.navigation) if s is not None]

    @property
    def name(self) -> str:
        return self.profile.name

    @property
    def capabilities(self) -> frozenset[str]:
        return self.hardware.capabilities

    def now(self) -> float:
        return self.hardware.clock.now()

    @property
    def tablet_url(self) -> str | None:
        """Where the tablet page is served (token included), or None without one."""
        return self.hardware.tablet_url

    @property
    def notes(self) -> list[str]:
        """What the user should know about the devices as opened (e.g. no microphone)."""
        return list(self.hardware.notes)

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
        for skill in (self.following, self.navigation, self.guide, self.speech, self.head,
                      self.questionnaire):
            if skill is not None and hasattr(skill, "cancel"):
                skill.cancel(now)

    @property
    def scenario_duration(self) -> float | None:
        return self.hardware.scenario_duration

    @property
    def scenario_people(self) -> int | None:
        return self.hardware.scenario_people

    def ground_truth(self) -> list[tuple[str, float, float]]:
        return self.hardware.ground_truth()

    def start_snapshots(self, inputs: bool = True) -> None:
        """Make `snapshot()` possible: the hardware starts logging its readings and commands
        (with `inputs`, the snapshot carries the exact readings that replay plays back)."""
        self.hardware.start_tap(inputs)

    def snapshot(self) -> dict:
        """This tick at L1 as plain data: every blackboard entry with its age, each skill's
        status with its reason, the people tracks and the user; `hardware` holds L0's part."""
        now = self.now()
        entries, statuses = {}, {}
        for key, entry in sorted(self.blackboard.entries().items()):
            if key.startswith(SKILL_STATUS_PREFIX):
                name = key[len(SKILL_STATUS_PREFIX):].rsplit("/", 1)[0]
                statuses[name] = {"status": entry.value.status.value, "reason": entry.value.reason,
                                  "age": round(now - entry.t, 3)}
                continue
            entries[key] = {"value": plain(entry.value), "age": round(now - entry.t, 3)}
        user = self.perception.user
        tracks = entries.get("people/tracks")       # the same confirmed tracks: made once
        return {
            "t": now,
            "blackboard": entries,
            "skills": statuses,
            "tracks": (tracks["value"] if tracks is not None
                       else [_track(t) for t in self.perception.tracks]),
            "user": None if user is None else user.id,
            "hardware": self.hardware.snapshot(),
        }

    def top_view(self) -> dict:
        """What a top view draws: walls and places where known, the robot's outline and sonar."""
        return self.hardware.top_view()

    def close(self) -> None:
        try:
            self._closing_events(self.localization.closing)     # a link that just went down
            self.hardware.close()
            self._closing_events(self.localization.closed)      # a stop closing could not send
        finally:
            self.blackboard.clear()

    def _closing_events(self, record) -> None:
        """Record the closing's link events; never let that keep the base from closing."""
        try:
            record(self.now())
        except Exception as exc:
            logging.getLogger("interbot.skills").warning("recording the closing failed: %s", exc)


def _track(track) -> dict:
    return {"id": track.id, "x": round(float(track.x), 3), "y": round(float(track.y), 3),
            "vx": round(float(track.vx), 3), "vy": round(float(track.vy), 3),
            "status": track.status}



def plain(value):
    """A blackboard value as JSON-able data (tracks, statuses and progress as small dicts);
    floats to 0.1 mm or better, which is all a reader of the snapshot needs."""
    kind = type(value)
    if kind is float:
        return round(value, 4) if value - value == 0.0 else None     # inf and nan: None
    if kind is tuple or kind is list:
        if value and all(type(v) is float for v in value):
            return [round(v, 4) if v - v == 0.0 else None for v in value]
        return [plain(v) for v in value]
    if value is None or kind is bool or kind is int or kind is str:
        return value
    if kind is Track:
        return _track(value)
    if kind is SkillStatus:
        return str(value)
    if kind is SurveyProgress:
        return {"answers": [list(a) for a in value.answers], "total": value.total,
                "asking": value.asking, "closed": value.closed,
                "last": None if value.last is None else list(value.last),
                "pending": value.pending}
    if isinstance(value, np.generic):
        return plain(value.item())
    return str(value)


def open_skills(robot: str | Path, *, port: str | None = None, scenario: str | Path | None = None,
                fast: bool = False, seed: int = 0, map: str | Path | GridMap | None = None,
                initial_pose: tuple[float, float, float] | None = None,
                gui: str | None = None, speech_wav: str | Path | None = None,
                language: str = "en", voice: str | None = None,
                listen: bool = False, replay=None, reset_faults: bool = False,
                devices: dict[str, str | None] | None = None, wire: bool = False) -> SkillSet:
    """Open the robot's hardware (real or simulated) and its skills.

    `map`: a bundled floor name, a floor .toml or a map_server .yaml, the map localization and
    navigation use (default: the simulated floor in simulation, none on a real robot). In
    simulation the simulated building is made from the same file (a scenario written for
    another floor or map is refused); a `GridMap` object is a map for localization alone.
    `initial_pose` (x m, y m, heading rad) where localization starts (default: the start pose
    in simulation, else the map's robot_home). The interaction options (tablet page, speech,
    listening) are the hardware's, see `robots.hardware.open_hardware`; `replay` plays a
    recording instead of hardware. A map that cannot be read, or a start pose that is not a
    free place on the map, is refused before the hardware opens."""
    floor = None
    if map is not None and not isinstance(map, GridMap):
        if port is None and replay is None:
            floor = map                   # in simulation the map is the simulated building too
        map = load_map(map)               # a MapError (a SkillError) names the file and field
    if initial_pose is not None and map is not None:    # else: checked on the simulated floor
        initial_pose = check_initial_pose(initial_pose, map)
    try:
        hardware = open_hardware(robot, port=port, scenario=scenario, fast=fast, seed=seed,
                                 gui=gui, speech_wav=speech_wav, language=language, voice=voice,
                                 listen=listen, replay=replay, reset_faults=reset_faults,
                                 devices=devices, wire=wire,
                                 floor=floor)
    except RobotError as exc:
        raise SkillError(str(exc)) from exc
    try:
        return SkillSet(hardware, map=map, initial_pose=initial_pose, seed=seed)
    except BaseException:      # Ctrl-C or SIGTERM while the skills are built: the base is open
        hardware.close()
        raise


# -- map and localization ----------------------------------------------------------------------

def _robot_map(hardware: Hardware, map: str | Path | GridMap | None) -> GridMap | None:
    """The map the robot localizes and navigates in: the one given, else the simulated floor,
    else none."""
    if isinstance(map, GridMap):
        return map
    if map is not None:
        return load_map(map)
    floor = hardware.floor
    if floor is None:
        return None
    key = (floor.name, floor.segments.tobytes(), tuple(sorted(floor.places.items())))
    if key not in _floor_maps:        # one grid per floor: its cost map and graph are cached on it
        _floor_maps[key] = map_from_floor(floor)
    return _floor_maps[key]


_floor_maps: dict[tuple, GridMap] = {}


def _camera_fov(profile) -> float:
    """The person detector's field of view (rad), 0 without one."""
    return profile.people_detector.fov if profile.people_detector is not None else 0.0


def _map_for_people(hardware: Hardware, grid: GridMap | None) -> GridMap | None:
    """The map people perception drops wall legs with: a user's map, and any map on a real
    robot; not a bundled simulated floor, whose laser has no drop-outs (its walls make no legs)
    and whose recorded runs replay unchanged (as robots/sim/laser_errors.py keeps them)."""
    floor = hardware.floor
    if floor is not None and getattr(floor, "source", None) is None:
        return None
    return grid


def _is_floor_map(hardware: Hardware, grid: GridMap | None) -> bool:
    """Whether `grid` is the simulated floor itself (drawn the same), so that the simulator's
    start pose is a pose on it."""
    if grid is None or hardware.floor is None:
        return False
    floor_map = _robot_map(hardware, None)
    return grid is floor_map or (
        grid.resolution == floor_map.resolution and grid.origin == floor_map.origin
        and np.array_equal(grid.occupied, floor_map.occupied)
        and _same_unknown(grid.unknown, floor_map.unknown))


def _same_unknown(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    """Unknown cells equal, no array counting as none unknown."""
    if a is None or b is None:
        return (a is None or not a.any()) and (b is None or not b.any())
    return np.array_equal(a, b)


def check_initial_pose(pose, grid: GridMap | None) -> tuple[float, float, float]:
    """(x m, y m, heading rad) as floats; refused (SkillError) unless three finite numbers on
    a free cell of the map. Without a map a start pose means nothing (the pose is the odometry)."""
    try:
        x, y, th = (float(v) for v in pose)
    except (TypeError, ValueError):
        raise SkillError(f"initial pose {pose!r} is not three numbers; allowed (x m, y m, "
                         "heading rad)") from None
    if not all(math.isfinite(v) for v in (x, y, th)):
        raise SkillError(f"initial pose ({x}, {y}, {th}) is not finite; allowed finite numbers")
    if grid is None:
        raise SkillError("an initial pose needs a map to be a pose on: this robot has none "
                         "(give a map: a floor name, a floor .toml or a map_server .yaml)")
    rows, cols = grid.to_cells(x, y)
    if not grid.inside(rows, cols):
        x0, y0 = grid.origin
        x1 = x0 + grid.shape[1] * grid.resolution
        y1 = y0 + grid.shape[0] * grid.resolution
        raise SkillError(f"initial pose ({x:g}, {y:g}) is off the map '{grid.name}'; allowed x "
                         f"{x0:.2f} .. {x1:.2f} m, y {y0:.2f} .. {y1:.2f} m")
    if not grid.free[rows, cols]:
        depth = _distance_to_free(grid, int(rows), int(cols))
        if depth > START_REACH:
            what = "a wall" if grid.occupied[rows, cols] else "unknown space"
            raise SkillError(f"initial pose ({x:g}, {y:g}) is {depth:.1f} m inside {what} of "
                             f"the map '{grid.name}'; allowed a free place or within "
                             f"{START_REACH:g} m of one{_home_example(grid)}")
    return x, y, math.atan2(math.sin(th), math.cos(th))


START_REACH = 1.0     # m: a start guess this close to free space is one the filter can correct
                      # (its first particle cloud has a standard deviation of 0.5 m)


def _distance_to_free(grid: GridMap, row: int, col: int) -> float:
    """Metres from a cell to the nearest free cell (inf when the map has none)."""
    free_rows, free_cols = np.nonzero(grid.free)
    if not len(free_rows):
        return math.inf
    return float(np.hypot(free_rows - row, free_cols - col).min()) * grid.resolution


def _home_example(grid: GridMap) -> str:
    home = grid.places.get("robot_home")
    if home is None:
        return ""
    return f" (e.g. robot_home {home[0]:g},{home[1]:g},{math.degrees(home[2]):g})"


def _localization(bb, ev, hardware: Hardware, grid: GridMap | None, initial_pose,
                  seed: int, own_floor: bool = False) -> Localization:
    """MCL with the laser (else the sonar ring) on the map; the odometry alone without one.

    Start pose: explicit, else the simulator's start pose, else the map's robot_home; with
    none of them the filter starts spread over the free map. Only the simulator's start on the
    simulator's own floor is known exactly (a tight particle cloud, `MCLParams.known_std`);
    any other start is a guess the first scans must correct (`MCLParams.initial_std`)."""
    profile = hardware.profile
    initial_std = None
    if initial_pose is None and hardware.start_pose is not None:
        initial_pose = hardware.start_pose
        if own_floor:
            initial_std = MCLParams().known_std
    if initial_pose is None and grid is not None:
        initial_pose = grid.places.get("robot_home")
    laser_range = profile.laser.max_range if profile.laser is not None else 8.0
    return Localization(bb, ev, hardware.base, grid=grid, laser=hardware.laser,
                        laser_range=laser_range, sonar=profile.sonar, initial_pose=initial_pose,
                        initial_std=initial_std, seed=seed)
