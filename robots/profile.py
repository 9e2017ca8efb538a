"""Robot profiles: what a robot is made of, read from TOML under `robots/profiles/`.

A profile names the base driver and port, the geometry, the speed and acceleration limits,
the sensors and the devices. Each layer reads its part: L0 opens the base, L1 picks methods
that fit the sensors, L2 picks behavior realizations by the capabilities listed here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from robots.exceptions import ProfileError, UnknownRobotError
from robots.tomlfile import read_toml

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


@dataclass(frozen=True)
class DetectorSpec:
    """The simulated person detector (a camera stand-in) and its error model."""
    range: float         # m
    fov: float           # rad, full field of view
    noise: float         # m, standard deviation of each coordinate
    miss_rate: float     # probability a visible person is not reported in a frame
    false_rate: float    # expected false detections per frame


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


def load_profile(name_or_path: str | Path) -> RobotProfile:
    """Load a bundled profile by name (`horos`) or any profile file by path."""
    path = Path(name_or_path)
    if path.suffix != ".toml":
        path = PROFILE_DIR / f"{name_or_path}.toml"
        if not path.exists():
            raise UnknownRobotError(
                f"unknown robot '{name_or_path}'; known robots: {', '.join(available_robots())}")
    data, _ = read_toml(path, ProfileError, "robot profile")
    return _ProfileReader(path, data).profile()


class _ProfileReader:
    """Turns the TOML tables into a RobotProfile, naming file and field on every error."""

    def __init__(self, path: Path, data: dict) -> None:
        self.path = path
        self.data = data

    def fail(self, key: str, why: str) -> ProfileError:
        return ProfileError(f"{self.path}: [{key}] {why}")

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
            raise self.fail(table, f"{key} = {value!r} is outside the allowed range {low} .. {high}")
        return float(value)

    def angle(self, table: str, key: str, low_deg: float, high_deg: float,
              default: float | None = None) -> float:
        return math.radians(self.number(table, key, low_deg, high_deg, default))

    def profile(self) -> RobotProfile:
        robot = self.table("robot")
        base = self.table("base")
        geometry = self.table("geometry")
        self.table("limits")
        shape = geometry.get("shape", "round")
        if shape not in ("round", "rectangle"):
            raise self.fail("geometry", f"shape = {shape!r}; allowed: 'round', 'rectangle'")
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
                        max_pan_rate=self.angle("head", "max_pan_rate_deg", 1.0, 720.0))

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
