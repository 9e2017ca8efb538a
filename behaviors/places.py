"""The places an application names, as the robot's map sees them: which are missing, which
the robot cannot drive to from its start. L3's `check --map` asks here; L1 plans
(`skills.navigation.reach`)."""
from __future__ import annotations

from pathlib import Path

from behaviors.exceptions import BehaviorError
from skills.exceptions import SkillError


class PlaceCheckError(BehaviorError):
    """The map or the robot could not be read for the check (the message says which, where)."""


def check_places(map_source: str | Path, robot: str, names, start: str = "robot_home"):
    """The verdict (`skills.navigation.reach.Reach`: `missing`, `unreachable` name -> reason,
    `places`, `reachable`) on `names` for `robot` starting at place `start` of the map."""
    from skills.navigation.reach import reach_on_map
    try:
        return reach_on_map(map_source, robot, list(names), start)
    except SkillError as exc:
        raise PlaceCheckError(str(exc)) from exc
