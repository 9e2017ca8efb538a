"""The two-wheel drive's parameters and its kinematics, pure: SI in, drive units out, and back.

Drive units are the vendor's (CiA 402 leaves them open; the factor group 0x608F/0x6091/0x6092
sets them on some drives): the profile names the velocity unit and the position unit separately
(`velocity_unit`, `position_unit`, each with a `_resolution`, the size of one drive unit in that
unit), so a drive with velocity in 0.1 rpm and position in encoder increments is described as
it is. Motor-side units (counts, rpm, rad, deg, revolutions) go through `gear_ratio` and the
wheel; rim units (mm, m, mm/s, m/s) mean the drive already applies gear and wheel (its feed
constant). Accelerations are velocity units per second. `DriveConfig` is read from the
profile's `[base]` table (docs/canopen.md).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields

from robots.exceptions import ProfileError

I32 = 2**32
# Per unit: (how many of it per metre of wheel travel, as a function of the config); velocity
# units per m/s likewise. Motor-side units scale with the gear, rim units do not.
VELOCITY_UNITS = {
    "counts/s": lambda c: c.encoder_counts * c.motor_turns_per_metre,
    "rpm": lambda c: 60.0 * c.motor_turns_per_metre,
    "rad/s": lambda c: 2 * math.pi * c.motor_turns_per_metre,
    "mm/s": lambda c: 1000.0,
    "m/s": lambda c: 1.0,
}
POSITION_UNITS = {
    "counts": lambda c: c.encoder_counts * c.motor_turns_per_metre,
    "revolutions": lambda c: c.motor_turns_per_metre,
    "rad": lambda c: 2 * math.pi * c.motor_turns_per_metre,
    "deg": lambda c: 360.0 * c.motor_turns_per_metre,
    "mm": lambda c: 1000.0,
    "m": lambda c: 1.0,
}


@dataclass(frozen=True)
class DriveConfig:
    wheel_radius: float = 0.0825        # m
    track_width: float = 0.42           # m, between the wheels' contact points
    encoder_counts: int = 4096          # increments per motor revolution (after quadrature)
    gear_ratio: float = 24.0            # motor revolutions per wheel revolution
    left_node: int = 1
    right_node: int = 2
    right_mirrored: bool = True         # the right motor is mounted mirrored: negate it
    sonar_node: int = 0                 # a sonar board sending ranges on SYNC (0 = none)
    sonars: int = 0
    heartbeat_ms: int = 100             # each drive's heartbeat period (0x1017)
    heartbeat_timeout_ms: int = 300     # a drive's heartbeat older than this: link down
    host_heartbeat_ms: int = 100        # the host's own heartbeat (node 0x7F)
    host_timeout_ms: int = 300          # the drives quick-stop without the host's heartbeat
    sync_period: float = 0.01           # s, SYNC (TPDOs on every SYNC)
    quick_stop_decel: float = 1.5       # m/s² at the wheel, on faults and the host timeout
    sdo_timeout: float = 0.3            # s per SDO answer (one retry)
    boot_timeout: float = 2.0           # s for the boot-up after NMT reset communication
    state_timeout: float = 0.5          # s for a CiA 402 state change to show in the statusword
    bitrate: int = 500_000
    velocity_unit: str = "counts/s"     # what the drive's velocity objects count in (VELOCITY_UNITS)
    velocity_resolution: float = 1.0    # one drive velocity unit, in velocity_unit (0.1 for 0.1 rpm)
    position_unit: str = "counts"       # what 0x6064 counts in (POSITION_UNITS)
    position_resolution: float = 1.0    # one drive position unit, in position_unit
    self_check: bool = True             # move each wheel a little at start-up, check the encoders
    self_check_distance: float = 0.02   # m of wheel travel in the self-check
    standstill_window: float = 0.01     # m/s at the wheel: below this a wheel stands still
    stop_timeout: float = 2.0           # s at most to wait for standstill when stopping

    @classmethod
    def field_names(cls) -> set[str]:
        return {f.name for f in fields(cls)}

    @classmethod
    def problems(cls, options: dict) -> list[tuple[str, str]]:
        """(key, why) for each field of `options` of the wrong type or out of range; keys that
        are not fields are left to the caller."""
        found, values = [], {}
        for key, value in options.items():
            if key not in cls.field_names():
                continue
            kind = type(getattr(cls, key))
            if kind is str and not isinstance(value, str):
                found.append((key, f"{key} = {value!r} must be a string"))
            elif kind is bool and not isinstance(value, bool):
                found.append((key, f"{key} = {value!r} must be true or false"))
            elif kind not in (str, bool) and (isinstance(value, bool) or not isinstance(value, (int, float))):
                found.append((key, f"{key} = {value!r} must be a number"))
            else:
                values[key] = kind(value)
        return found or list(cls(**values).value_problems())

    @classmethod
    def from_options(cls, options: dict, where: str = "profile [base]") -> "DriveConfig":
        """Build from the profile's base options; unknown keys are left to the caller."""
        found = cls.problems(options)
        if found:
            raise ProfileError(f"{where}: {found[0][1]}")
        return cls(**{k: type(getattr(cls, k))(v) for k, v in options.items() if k in cls.field_names()})

    def check(self, where: str) -> None:
        for _, why in self.value_problems():
            raise ProfileError(f"{where}: {why}")

    def value_problems(self):
        """(key, why) for each value outside its range or inconsistent with another."""
        for key, low, high in (("wheel_radius", 0.01, 1.0), ("track_width", 0.05, 3.0),
                               ("encoder_counts", 1, 2**24), ("gear_ratio", 0.01, 1000.0),
                               ("left_node", 1, 127), ("right_node", 1, 127),
                               ("sonar_node", 0, 127), ("sonars", 0, 16),
                               ("heartbeat_ms", 10, 10_000), ("heartbeat_timeout_ms", 20, 60_000),
                               ("host_heartbeat_ms", 10, 10_000), ("host_timeout_ms", 20, 60_000),
                               ("sync_period", 0.001, 1.0), ("quick_stop_decel", 0.05, 20.0),
                               ("sdo_timeout", 0.01, 10.0), ("boot_timeout", 0.0, 60.0),
                               ("state_timeout", 0.01, 10.0), ("bitrate", 10_000, 1_000_000),
                               ("velocity_resolution", 1e-9, 1e9), ("position_resolution", 1e-9, 1e9),
                               ("self_check_distance", 0.002, 0.5), ("standstill_window", 0.0005, 0.5),
                               ("stop_timeout", 0.05, 30.0)):
            value = getattr(self, key)
            if not low <= value <= high:
                yield key, f"{key} = {value} outside the allowed range {low} .. {high}"
        for key, known in (("velocity_unit", VELOCITY_UNITS), ("position_unit", POSITION_UNITS)):
            if getattr(self, key) not in known:
                yield key, (f"{key} = {getattr(self, key)!r}; allowed: "
                            f"{', '.join(repr(k) for k in known)}")
        if self.left_node == self.right_node:
            yield "right_node", f"left_node and right_node are both {self.left_node}"
        if self.heartbeat_timeout_ms <= self.heartbeat_ms:
            yield "heartbeat_timeout_ms", (f"heartbeat_timeout_ms ({self.heartbeat_timeout_ms}) must "
                                           f"exceed heartbeat_ms ({self.heartbeat_ms})")
        if self.host_timeout_ms <= self.host_heartbeat_ms:
            yield "host_timeout_ms", (f"host_timeout_ms ({self.host_timeout_ms}) must exceed "
                                      f"host_heartbeat_ms ({self.host_heartbeat_ms})")

    # -- scale -------------------------------------------------------------------------------------
    @property
    def motor_turns_per_metre(self) -> float:
        return self.gear_ratio / (2 * math.pi * self.wheel_radius)

    @property
    def counts_per_metre(self) -> float:
        """Encoder increments per metre of wheel travel."""
        return self.encoder_counts * self.motor_turns_per_metre

    @property
    def velocity_per_mps(self) -> float:
        """Drive velocity units per m/s at the wheel rim."""
        return VELOCITY_UNITS[self.velocity_unit](self) / self.velocity_resolution

    @property
    def position_per_metre(self) -> float:
        """Drive position units per metre of wheel travel."""
        return POSITION_UNITS[self.position_unit](self) / self.position_resolution

    def sign(self, node: int) -> int:
        return -1 if (node == self.right_node and self.right_mirrored) else 1

    def wheel_name(self, node: int) -> str:
        return {self.left_node: "left wheel", self.right_node: "right wheel",
                self.sonar_node: "sonar board"}.get(node, "unknown node")

    def to_counts(self, metres_per_s: float, node: int) -> int:
        """A wheel speed (m/s, forward positive) as the drive's target velocity."""
        return round(metres_per_s * self.velocity_per_mps) * self.sign(node)

    def velocity_mps(self, units: float, node: int) -> float:
        """The drive's velocity (0x606C) as the wheel's forward speed in m/s."""
        return units * self.sign(node) / self.velocity_per_mps

    def travel_metres(self, units: float, node: int) -> float:
        """A change of the drive's position (0x6064) as forward wheel travel in m."""
        return units * self.sign(node) / self.position_per_metre

    def wheel_speeds(self, v: float, w: float) -> tuple[float, float]:
        """(left, right) wheel speeds in m/s for body speeds v (m/s), w (rad/s)."""
        half = w * self.track_width / 2
        return v - half, v + half

    def body_speeds(self, left: float, right: float) -> tuple[float, float]:
        """(v, w) of the body for wheel speeds in m/s."""
        return (left + right) / 2, (right - left) / self.track_width

    def command_counts(self, v: float, w: float) -> tuple[int, int]:
        """Target velocities (left node, right node) in drive units."""
        left, right = self.wheel_speeds(v, w)
        return self.to_counts(left, self.left_node), self.to_counts(right, self.right_node)

    def accel_counts(self, metres_per_s2: float) -> int:
        """An acceleration at the rim in the drive's units (velocity units per second)."""
        return max(1, round(metres_per_s2 * self.velocity_per_mps))


def wrap_delta(new: int, old: int) -> int:
    """new - old for 32-bit position counters that wrap."""
    return (new - old + 2**31) % I32 - 2**31


class Odometry:
    """Dead reckoning from the two wheels' position counters (midpoint integration)."""

    def __init__(self, config: DriveConfig) -> None:
        self.config = config
        self.x = self.y = self.th = 0.0
        self._last: tuple[int, int] | None = None

    def reset(self) -> None:
        """Forget the counters (a drive rebooted); the pose is kept."""
        self._last = None

    def update(self, left_counts: int, right_counts: int) -> tuple[float, float, float]:
        c = self.config
        if self._last is not None:
            dl = c.travel_metres(wrap_delta(left_counts, self._last[0]), c.left_node)
            dr = c.travel_metres(wrap_delta(right_counts, self._last[1]), c.right_node)
            ds, dth = (dl + dr) / 2, (dr - dl) / c.track_width
            mid = self.th + dth / 2
            self.x += ds * math.cos(mid)
            self.y += ds * math.sin(mid)
            self.th = (self.th + dth + math.pi) % (2 * math.pi) - math.pi
        self._last = (left_counts, right_counts)
        return self.x, self.y, self.th
