"""Robot profiles: what a robot is made of, read from TOML under `robots/profiles/` or from any
file (`--robot ./my_robot.toml`); every error names the file and line.

A profile names the base driver and port, the geometry, the speed and acceleration limits,
the sensors and the devices. Each layer reads its part: L0 opens the base, L1 picks methods
that fit the sensors, L2 picks behavior realizations by the capabilities listed here.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from robots.exceptions import ProfileError, UnknownRobotError
from robots.tomlfile import key_line, read_toml

PROFILE_DIR = Path(__file__).with_name("profiles")


@dataclass(frozen=True)
class BaseSpec:
    driver: str          # "p2os", "rflex", "canopen"
    port: str            # the serial port of the real robot
    baud: int
    options: dict = field(default_factory=dict)  # driver-specific constants (subclass, factors)


@dataclass(frozen=True)
class Limits:
    max_speed: float              # m/s, forward or backward
    max_turn_rate: float          # rad/s
    max_accel: float              # m/s^2
    max_turn_accel: float         # rad/s^2
    max_speed_near_people: float  # m/s, cap within `near_people_distance`
    near_people_distance: float   # m


@dataclass(frozen=True)
class SonarSpec:
    poses: np.ndarray    # (n, 3): x, y in m and heading in rad, robot frame
    max_range: float     # m
    cone: float          # rad, full opening angle


@dataclass(frozen=True)
class LaserSpec:
    x: float
    y: float
    heading: float       # rad
    fov: float           # rad, full field of view
    beams: int
    max_range: float     # m
    noise: float         # m, standard deviation
    device: str | None = None   # the real laser: "kind:address[?options]" (robots.lasers)


@dataclass(frozen=True)
class HeadSpec:
    pan_min: float       # rad
    pan_max: float
    tilt_min: float
    tilt_max: float
    max_pan_rate: float  # rad/s
    model: str = "evi-d31"   # the VISCA camera model (robots.visca), for a real head
    device: str = ""         # where the real head is: "visca:/dev/ttyUSB1"; in simulation its
    #                          emulator stands there (robots.real_devices)


@dataclass(frozen=True)
class DetectorSpec:
    """The simulated person detector (a camera stand-in) and its error model."""
    range: float         # m
    fov: float           # rad, full field of view
    noise: float         # m, standard deviation of each coordinate
    miss_rate: float     # probability a visible person is not reported in a frame
    false_rate: float    # expected false detections per frame


@dataclass(frozen=True)
class CameraSpec:
    """A real camera used as a person detector (table `[camera]`, robots.camera): where it is,
    its lens, what it looks for and how sure a detection is. Without a `device` it is not
    used; with one, a simulated run draws the world for it (robots.real_devices)."""
    device: str = ""             # a device index, /dev/video path, URL or video file (with --port)
    calibration: str = ""        # an OpenCV calibration file, relative to the profile's folder
    hfov_deg: float = 48.8       # horizontal field of view when there is no calibration file
    width: int = 640             # px
    height: int = 480
    x: float = 0.0               # m, robot frame
    y: float = 0.0
    heading: float = 0.0         # rad
    on_head: bool = False        # it turns with the pan-tilt head (a camera head)
    detect: tuple[str, ...] = ("body", "face")
    person_height: float = 1.7   # m, to range a whole person from the box height
    face_size: float = 0.19      # m, the height a face box spans at the person
    bearing_sd: float = math.radians(2.0)   # rad, one standard deviation
    range_sd: float = 0.2        # fraction of the range, one standard deviation
    max_range: float = 8.0       # m, farther detections are dropped


@dataclass(frozen=True)
class OdometrySpec:
    """Wheel-odometry error of the simulated base (table `[odometry]`, all optional).

    Per metre driven and radian turned, the odometry the simulated base reports differs from
    the body's true motion by a systematic part (miscalibrated wheel diameter and wheel base,
    unequal wheels) and a random part whose variance grows linearly with the distance and the
    angle (a random walk). A real base has the same kinds of error; zeros make it exact."""
    scale_error: float = 0.01        # fraction: reported distance = true · (1 + scale_error)
    turn_error: float = 0.02         # fraction: reported rotation = true · (1 + turn_error)
    drift: float = math.radians(0.5)  # rad of heading error per metre driven (unequal wheels)
    noise_distance: float = 0.01     # m standard deviation per √m driven
    noise_turn: float = 0.02         # rad standard deviation per √rad turned
    noise_heading: float = math.radians(0.5)  # rad standard deviation per √m driven

    @property
    def exact(self) -> bool:
        return not any((self.scale_error, self.turn_error, self.drift, self.noise_distance,
                        self.noise_turn, self.noise_heading))


@dataclass(frozen=True)
class RobotProfile:
    name: str
    description: str
    source: Path
    base: BaseSpec
    radius: float        # m, bounding circle used for collisions
    shape: str           # "rectangle" or "round"
    length: float
    width: float
    limits: Limits
    sonar: SonarSpec | None
    laser: LaserSpec | None
    head: HeadSpec | None
    touch_screen: bool
    speech: bool
    people_detector: DetectorSpec | None
    odometry: OdometrySpec = field(default_factory=OdometrySpec)
    speech_input: bool = False      # a microphone for spoken answers ([speech] input)
    camera: CameraSpec | None = None    # a real camera ([camera]), where it names a device

    @property
    def capabilities(self) -> frozenset[str]:
        """Names behaviors use to choose a realization (e.g. pan_tilt vs. body turn)."""
        caps = {"base"}
        if self.sonar is not None:
            caps.add("sonar")
        if self.laser is not None:
            caps.add("laser")
        if self.head is not None:
            caps.add("pan_tilt")
        if self.touch_screen:
            caps.add("touch_screen")
        if self.speech:
            caps.add("speech_out")
        if self.speech_input:
            caps.add("speech_in")
        if self.people_detector is not None:
            caps.add("people_detector")
        return frozenset(caps)


def available_robots() -> list[str]:
    """Names of the bundled robot profiles."""
    return sorted(p.stem for p in PROFILE_DIR.glob("*.toml"))


def is_profile_file(robot: str | Path) -> bool:
    """A robot given as a file (`./my_robot.toml`, `robots/x.toml`) rather than a bundled name."""
    text = str(robot)
    return isinstance(robot, Path) or text.endswith(".toml") or "/" in text or os.sep in text


def load_profile(name_or_path: str | Path) -> RobotProfile:
    """Load a bundled profile by name (`horos`) or any profile file by path."""
    if is_profile_file(name_or_path):
        path = Path(name_or_path).expanduser()
        if not path.is_file():
            raise ProfileError(f"{path}: no such robot profile file (a robot is a bundled name, "
                               f"{', '.join(available_robots())}, or a .toml file)")
    else:
        path = PROFILE_DIR / f"{name_or_path}.toml"
        if not path.exists():
            raise UnknownRobotError(
                f"unknown robot '{name_or_path}'; known robots: {', '.join(available_robots())} "
                f"(or give a profile file, e.g. --robot ./my_robot.toml)")
    data, text = read_toml(path, ProfileError, "robot profile")
    return _ProfileReader(path, data, text).profile()


STRICT_TABLES = {       # tables whose keys are all known here; the others may carry devices' keys
    "geometry": {"shape", "radius", "length", "width"},
    "limits": {"max_speed", "max_turn_rate_deg", "max_accel", "max_turn_accel_deg",
               "max_speed_near_people", "near_people_distance"},
}
BASE_KEYS = {"driver", "port", "baud"}


class _ProfileReader:
    """Turns the TOML tables into a RobotProfile, naming file and field on every error."""

    def __init__(self, path: Path, data: dict, text: str = "") -> None:
        self.path = path
        self.data = data
        self.source = text          # the file's text, for the line of a key

    def fail(self, table: str, why: str, key: str | None = None) -> ProfileError:
        """`file:line: [table] why`, the line of `key` (or of the table) where it is written."""
        line = (key_line(self.source, table, key) if key else None) or key_line(self.source, table)
        return ProfileError(f"{self.path}{f':{line}' if line else ''}: [{table}] {why}")

    def table(self, key: str, required: bool = True) -> dict | None:
        value = self.data.get(key)
        if value is None:
            if required:
                raise self.fail(key, "table is missing")
            return None
        if not isinstance(value, dict):
            raise self.fail(key, "must be a table")
        return value

    def number(self, table: str, key: str, low: float, high: float, default: float | None = None) -> float:
        value = self.data.get(table, {}).get(key, default)
        if value is None:
            raise self.fail(table, f"{key} is missing (allowed {low} .. {high})")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
            raise self.fail(table, f"{key} = {value!r} is outside the allowed range {low} .. {high}", key)
        return float(value)

    def check_keys(self) -> None:
        """Unknown keys in the tables whose keys are all known (a typo would silently be a
        default), and the base driver's own options, each at its line."""
        for table, known in STRICT_TABLES.items():
            for key in self.data.get(table, {}) if isinstance(self.data.get(table), dict) else ():
                if key not in known:
                    raise self.fail(table, f"unknown key {key!r}{_did_you_mean(key, known)}; "
                                    f"known: {', '.join(sorted(known))}", key)
        base = self.data.get("base", {})
        driver = base.get("driver")
        from robots.base import base_classes       # the plugins (a base imports this module)
        classes = base_classes()
        if driver not in classes:
            raise self.fail("base", f"driver = {driver!r}; known drivers: {', '.join(sorted(classes))}",
                            "driver")
        options = {k: v for k, v in base.items() if k not in BASE_KEYS}
        check = getattr(classes[driver], "profile_problems", None)
        for key, why in (check(options) if check is not None else []):
            raise self.fail("base", why, key)

    def angle(self, table: str, key: str, low_deg: float, high_deg: float,
              default: float | None = None) -> float:
        return math.radians(self.number(table, key, low_deg, high_deg, default))

    def profile(self) -> RobotProfile:
        robot = self.table("robot")
        base = self.table("base")
        geometry = self.table("geometry")
        self.table("limits")
        self.check_keys()
        shape = geometry.get("shape", "round")
        if shape not in ("round", "rectangle"):
            raise self.fail("geometry", f"shape = {shape!r}; allowed: 'round', 'rectangle'", "shape")
        return RobotProfile(
            name=str(robot.get("name", self.path.stem)),
            description=str(robot.get("description", "")),
            source=self.path,
            base=BaseSpec(
                driver=str(base.get("driver", "")),
                port=str(base.get("port", "")),
                baud=int(self.number("base", "baud", 300, 4_000_000, 9600)),
                options={k: v for k, v in base.items() if k not in ("driver", "port", "baud")},
            ),
            radius=self.number("geometry", "radius", 0.05, 2.0),
            shape=shape,
            length=self.number("geometry", "length", 0.05, 4.0, 2 * geometry.get("radius", 0.3)),
            width=self.number("geometry", "width", 0.05, 4.0, 2 * geometry.get("radius", 0.3)),
            limits=self.limits(),
            sonar=self.sonar(),
            laser=self.laser(),
            head=self.head(),
            touch_screen=bool(self.data.get("screen", {}).get("touch", False)),
            speech=bool(self.data.get("speech", {}).get("output", True)),
            people_detector=self.detector(),
            odometry=self.odometry(),
            speech_input=bool(self.data.get("speech", {}).get("input", False)),
            camera=self.camera(),
        )

    def limits(self) -> Limits:
        return Limits(
            max_speed=self.number("limits", "max_speed", 0.0, 3.0),
            max_turn_rate=self.angle("limits", "max_turn_rate_deg", 0.0, 720.0),
            max_accel=self.number("limits", "max_accel", 0.01, 5.0),
            max_turn_accel=self.angle("limits", "max_turn_accel_deg", 1.0, 2000.0),
            max_speed_near_people=self.number("limits", "max_speed_near_people", 0.0, 3.0),
            near_people_distance=self.number("limits", "near_people_distance", 0.0, 10.0, 1.5),
        )

    def sonar(self) -> SonarSpec | None:
        table = self.table("sonar", required=False)
        if table is None:
            return None
        poses = table.get("poses")
        if not isinstance(poses, list) or not poses or any(
                not isinstance(p, list) or len(p) != 3 for p in poses):
            raise self.fail("sonar", "poses must be a list of [x_m, y_m, heading_deg] triples")
        array = np.array(poses, dtype=float)
        array[:, 2] = np.radians(array[:, 2])
        return SonarSpec(poses=array,
                         max_range=self.number("sonar", "max_range", 0.1, 20.0),
                         cone=self.angle("sonar", "cone_deg", 1.0, 90.0, 30.0))

    def laser(self) -> LaserSpec | None:
        if self.table("laser", required=False) is None:
            return None
        return LaserSpec(x=self.number("laser", "x", -2.0, 2.0, 0.0),
                         y=self.number("laser", "y", -2.0, 2.0, 0.0),
                         heading=self.angle("laser", "heading_deg", -180.0, 180.0, 0.0),
                         fov=self.angle("laser", "fov_deg", 1.0, 360.0),
                         beams=int(self.number("laser", "beams", 2, 4000)),
                         max_range=self.number("laser", "max_range", 0.5, 80.0),
                         noise=self.number("laser", "noise", 0.0, 1.0, 0.01),
                         device=self.laser_device())

    def laser_device(self) -> str | None:
        """[laser] device, checked (kind, address, options) before anything is opened."""
        value = self.data["laser"].get("device")
        if value is None:
            return None
        from robots.lasers import parse_laser_device
        if not isinstance(value, str):
            raise self.fail("laser", f"device = {value!r} must be a string like "
                                     f"\"lms200:/dev/ttyUSB0?baud=38400\"")
        try:
            parse_laser_device(value)
        except ValueError as exc:
            raise self.fail("laser", f"device = {value!r}: {exc}") from None
        return value

    def head(self) -> HeadSpec | None:
        if self.table("head", required=False) is None:
            return None
        return HeadSpec(pan_min=self.angle("head", "pan_min_deg", -180.0, 0.0),
                        pan_max=self.angle("head", "pan_max_deg", 0.0, 180.0),
                        tilt_min=self.angle("head", "tilt_min_deg", -90.0, 0.0),
                        tilt_max=self.angle("head", "tilt_max_deg", 0.0, 90.0),
                        max_pan_rate=self.angle("head", "max_pan_rate_deg", 1.0, 720.0),
                        model=self.choice("head", "model", ("evi-d31", "evi-d70"), "evi-d31"),
                        device=self.text("head", "device", ""))

    def choice(self, table: str, key: str, allowed: tuple[str, ...], default: str) -> str:
        value = self.data.get(table, {}).get(key, default)
        if value not in allowed:
            raise self.fail(table, f"{key} = {value!r}; allowed: {', '.join(map(repr, allowed))}")
        return value

    def text(self, table: str, key: str, default: str) -> str:
        value = self.data.get(table, {}).get(key, default)
        if not isinstance(value, str):
            raise self.fail(table, f"{key} = {value!r} must be a string")
        return value

    def camera(self) -> CameraSpec | None:
        table = self.table("camera", required=False)
        if table is None:
            return None
        known = set(CameraSpec.__dataclass_fields__) - {"heading", "bearing_sd"} | {
            "heading_deg", "bearing_sd_deg"}
        unknown = set(table) - known
        if unknown:
            raise self.fail("camera", f"unknown key(s) {', '.join(sorted(unknown))}; "
                            f"known: {', '.join(sorted(known))}")
        detect = table.get("detect", ["body", "face"])
        if not isinstance(detect, list) or not detect or \
                not set(detect) <= {"body", "face"}:
            raise self.fail("camera", f"detect = {detect!r}; allowed a non-empty list of "
                            f"'body', 'face'")
        d = CameraSpec()
        return CameraSpec(
            device=self.text("camera", "device", ""),
            calibration=self.text("camera", "calibration", ""),
            hfov_deg=self.number("camera", "hfov_deg", 1.0, 179.0, d.hfov_deg),
            width=int(self.number("camera", "width", 16, 10000, d.width)),
            height=int(self.number("camera", "height", 16, 10000, d.height)),
            x=self.number("camera", "x", -2.0, 2.0, 0.0),
            y=self.number("camera", "y", -2.0, 2.0, 0.0),
            heading=self.angle("camera", "heading_deg", -180.0, 180.0, 0.0),
            on_head=bool(table.get("on_head", False)),
            detect=tuple(detect),
            person_height=self.number("camera", "person_height", 0.5, 2.5, d.person_height),
            face_size=self.number("camera", "face_size", 0.05, 0.5, d.face_size),
            bearing_sd=self.angle("camera", "bearing_sd_deg", 0.01, 30.0, 2.0),
            range_sd=self.number("camera", "range_sd", 0.01, 2.0, d.range_sd),
            max_range=self.number("camera", "max_range", 0.5, 50.0, d.max_range))

    def odometry(self) -> OdometrySpec:
        """The simulated odometry error; each key defaults to `OdometrySpec`'s value."""
        if self.table("odometry", required=False) is None:
            return OdometrySpec()
        known = {"scale_error", "turn_error", "drift_deg_per_m", "noise_m_per_sqrt_m",
                 "noise_deg_per_sqrt_deg", "noise_deg_per_sqrt_m"}
        unknown = set(self.data["odometry"]) - known
        if unknown:
            raise self.fail("odometry", f"unknown key(s) {', '.join(sorted(unknown))}; "
                            f"known: {', '.join(sorted(known))}")
        d = OdometrySpec()
        per_sqrt_deg = math.sqrt(math.degrees(1.0))        # deg/√deg -> rad/√rad
        return OdometrySpec(
            scale_error=self.number("odometry", "scale_error", -0.2, 0.2, d.scale_error),
            turn_error=self.number("odometry", "turn_error", -0.2, 0.2, d.turn_error),
            drift=self.angle("odometry", "drift_deg_per_m", -10.0, 10.0, math.degrees(d.drift)),
            noise_distance=self.number("odometry", "noise_m_per_sqrt_m", 0.0, 0.5,
                                       d.noise_distance),
            noise_turn=self.angle("odometry", "noise_deg_per_sqrt_deg", 0.0, 5.0,
                                  math.degrees(d.noise_turn) / per_sqrt_deg) * per_sqrt_deg,
            noise_heading=self.angle("odometry", "noise_deg_per_sqrt_m", 0.0, 10.0,
                                     math.degrees(d.noise_heading)))

    def detector(self) -> DetectorSpec | None:
        if self.table("people_detector", required=False) is None:
            return None
        return DetectorSpec(range=self.number("people_detector", "range", 0.5, 30.0),
                            fov=self.angle("people_detector", "fov_deg", 1.0, 360.0),
                            noise=self.number("people_detector", "noise", 0.0, 2.0),
                            miss_rate=self.number("people_detector", "miss_rate", 0.0, 1.0),
                            false_rate=self.number("people_detector", "false_rate", 0.0, 10.0))


def _did_you_mean(word: str, known) -> str:
    import difflib
    close = difflib.get_close_matches(word, sorted(known), n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""
