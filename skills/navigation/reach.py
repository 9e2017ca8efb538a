"""Which places of a map a robot can drive to from where it starts: the planner's verdict for
each, before anything moves (`interbot check APP --map FILE` asks this through L2).

A place is *missing* when the map has no such name, *unreachable* when the global planner finds
no path to it for a robot of that radius (a wall, a door narrower than the robot, unknown space
around it), with the planner's reason.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from skills.navigation.costmap import cost_map
from skills.navigation.gridmap import GridMap, MapError
from skills.navigation.planner import GlobalPlanner

START = "robot_home"


@dataclass(frozen=True)
class Reach:
    """The verdict on some places: those missing, those unreachable (name -> reason)."""
    map_name: str
    start: str
    radius: float
    places: tuple[str, ...]                    # every place of the map, sorted
    missing: tuple[str, ...] = ()
    unreachable: dict[str, str] = field(default_factory=dict)

    @property
    def reachable(self) -> tuple[str, ...]:
        """The map's places the robot can drive to from the start."""
        return tuple(p for p in self.places if p not in self.unreachable)


def reach(grid: GridMap, radius: float, names, start: str = START) -> Reach:
    """Check each of `names` on `grid` for a robot of bounding `radius` m starting at place
    `start`; every place of the map is planned to, so `Reach.reachable` is complete."""
    places = tuple(sorted(grid.places))
    if start not in grid.places:
        raise MapError(f"map '{grid.name}' has no place '{start}', where the robot starts; "
                       f"places: {', '.join(places) or 'none'}")
    planner = GlobalPlanner(cost_map(grid, radius))
    origin = grid.places[start][:2]
    unreachable = {}
    for name in places:
        plan = planner.plan(origin, grid.places[name][:2])
        if not plan.found:
            unreachable[name] = plan.reason
    missing = tuple(dict.fromkeys(n for n in names if n not in grid.places))
    return Reach(grid.name, start, radius, places, missing, unreachable)





def reach_on_map(map_source, robot: str, names, start: str = START) -> Reach:
    """`reach` on a map given as a floor name, floor .toml or map_server .yaml, for the robot
    profile `robot`'s radius; a MapError (a SkillError) names the file and field, or the robot."""
    from robots.exceptions import ProfileError
    from robots.profile import load_profile
    from skills.navigation.gridmap import load_map
    try:
        radius = load_profile(robot).radius
    except ProfileError as exc:
        raise MapError(str(exc)) from None
    return reach(load_map(map_source), radius, names, start)
__all__ = ["Reach", "reach", "reach_on_map", "START"]
