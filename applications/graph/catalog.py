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

    @classmethod
    def empty(cls) -> "Catalog":
        return cls(None, None, None, None)


def load_catalog(robot: str | None) -> Catalog:
    """The registry and robot capabilities from L2, as far as L2 provides them."""
    behaviors = _behavior_specs()
    robots = _available_robots()
    capabilities = None
    if robot is not None and (robots is None or robot in robots):
        capabilities = _robot_capabilities(robot)
    return Catalog(behaviors, robots, robot, capabilities)


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


def _robot_capabilities(robot: str) -> frozenset[str] | None:
    try:
        from behaviors import robot_capabilities
    except ImportError:
        return None
    return frozenset(robot_capabilities(robot))
