"""The small interface every mobile base implements: drivers, and the in-process simulated base.

Like python-can's `BusABC`, the interface is an abstract class and the implementations are
plugins found by entry point (group `interbot.bases`). Units are SI throughout: metres,
seconds, radians; velocities in m/s and rad/s.
"""
from __future__ import annotations

import functools
import math
import sys
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from importlib.metadata import entry_points

from robots.exceptions import RobotError
from robots.profile import Limits


@dataclass(frozen=True)
class BaseState:
    """The newest state a base reported. `t` is robot time (the hardware clock) of its arrival."""
    t: float
    x: float = 0.0
    y: float = 0.0
    th: float = 0.0
    v: float = 0.0                      # m/s, measured
    w: float = 0.0                      # rad/s, measured
    sonar: tuple[float, ...] = ()       # m per sonar index; math.inf when no echo
    bumpers: int = 0                    # bit mask, bit i = bumper i pressed
    stalled: bool = False
    motors_enabled: bool = False
    battery: float = math.nan           # V
    link_up: bool = True
    extra: dict = field(default_factory=dict)


class Base(ABC):
    """A mobile base. `open` connects, `read_state` never blocks, `command` is clamped."""

    def __init__(self, limits: Limits) -> None:
        self.limits = limits

    @abstractmethod
    def open(self) -> None:
        """Connect and make the base ready to drive (motors enabled, sensors on)."""

    @abstractmethod
    def read_state(self) -> BaseState:
        """The newest state; never blocks."""

    @abstractmethod
    def command(self, v: float, w: float) -> None:
        """Drive at `v` m/s and `w` rad/s, clamped to the profile's limits (NaN becomes zero)."""

    @abstractmethod
    def stop(self) -> None:
        """Zero velocity now."""

    @abstractmethod
    def close(self) -> None:
        """Stop and release the link. Safe to call twice."""

    def poll(self, timeout: float = 0.0) -> None:
        """Process pending I/O. Threaded drivers need nothing here; lock-step simulations do."""

    @classmethod
    def profile_problems(cls, options: dict) -> list[tuple[str, str]]:
        """(key, why) for each option of a profile's [base] table this driver would refuse or
        ignore, checked when the profile is read so that the message names file and line
        (`driver`, `port`, `baud` are the profile's own). Default: none checked."""
        return []

    def __enter__(self) -> "Base":
        self.open()
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def clamp_velocity(v: float, w: float, limits: Limits) -> tuple[float, float]:
    """Clamp a command to the limits; NaN or infinite components become zero (safe default)."""
    v = float(v) if math.isfinite(v) else 0.0
    w = float(w) if math.isfinite(w) else 0.0
    v = max(-limits.max_speed, min(limits.max_speed, v))
    w = max(-limits.max_turn_rate, min(limits.max_turn_rate, w))
    return v, w


def base_classes() -> dict[str, type[Base]]:
    """Base implementations registered under the entry-point group `interbot.bases`."""
    found = {}
    for ep in _registered_bases(tuple(sys.path)):
        try:
            found[ep.name] = ep.load()
        except Exception as exc:  # a broken plugin must not hide the others
            raise RobotError(f"base plugin '{ep.name}' ({ep.value}) failed to load: {exc}") from exc
    return found


@functools.lru_cache(maxsize=4)
def _registered_bases(search_path: tuple[str, ...]):
    """The `interbot.bases` entry points, read once per import path: reading them scans every
    installed package's metadata (20-35 ms here), and each profile load asks for them; a
    changed `sys.path` (a plugin folder added at run time) reads them again."""
    return entry_points(group="interbot.bases")
