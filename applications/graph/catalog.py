"""What the layer below offers, as the checker sees it: the behavior registry and the chosen
robot's capabilities. Read through `behaviors` (L2) only; absent pieces make their checks skip."""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Catalog:
    behaviors: Mapping[str, Any] | None        # name -> BehaviorSpec, None when unavailable
    robots: tuple[str, ...] | None             # known robot names, None when unavailable
    robot: str | None                          # the robot the check is for
    capabilities: frozenset[str] | None        # that robot's capabilities
    robot_file: bool = False                   # the robot is a profile file, not a bundled name
    robot_error: str | None = None             # why that file could not be read (file:line)

    @classmethod
    def empty(cls) -> "Catalog":
        return cls(None, None, None, None)


def load_catalog(robot: str | None) -> Catalog:
    """The registry and robot capabilities from L2, as far as L2 provides them."""
    behaviors = _behavior_specs()
    robots = _available_robots()
    capabilities = error = None
    is_file = robot is not None and _is_robot_file(robot)
    if robot is not None and (robots is None or robot in robots or is_file):
        try:
            capabilities = _robot_capabilities(robot)
        except Exception as exc:          # a profile file with an error: reported, file:line
            if not is_file:
                raise
            error = str(exc)
    return Catalog(behaviors, robots, robot, capabilities, is_file, error)


def _behavior_specs() -> Mapping[str, Any] | None:
    try:
        from behaviors.registry import behavior_specs
    except ImportError:
        return None
    return behavior_specs()


def _available_robots() -> tuple[str, ...] | None:
    try:
        from behaviors import available_robots
    except ImportError:
        return None
    return tuple(available_robots())


def _is_robot_file(robot: str) -> bool:
    try:
        from behaviors import is_robot_file
    except ImportError:
        return False
    return is_robot_file(robot)


def _robot_capabilities(robot: str) -> frozenset[str] | None:
    try:
        from behaviors import robot_capabilities
    except ImportError:
        return None
    return frozenset(robot_capabilities(robot))
