"""The navigation and guide percepts: where the drive stands, how the follower keeps up, home.

They read `navigation/state` (the navigation skill), `guide/state` (the guiding skill) and the
pose against the map's `robot_home` place. On a robot without a map they are absent (a bool
reads as false): there is no navigation to report on.
"""
from __future__ import annotations

import math

from behaviors.percepts import PerceptContext, PerceptProvider, spec
from skills.guiding import ARRIVED as GUIDE_ARRIVED
from skills.guiding import GAVE_UP, OUTCOME_USER_LOST, WAITING
from skills.navigation.navigation import (ARRIVED, BLOCKED, BLOCKED_GAVE_UP, DRIVING, FAILED,
                                          LOCALIZATION_LOST, NO_PATH, PAUSED, TURNING,
                                          UNKNOWN_PLACE)

HOME = "robot_home"
AT_HOME = 0.3              # m from the robot_home place counted as at home
FAILURES = (NO_PATH, BLOCKED_GAVE_UP, LOCALIZATION_LOST, UNKNOWN_PLACE)
RUNNING_PHASES = (DRIVING, TURNING, PAUSED, BLOCKED)

SPECS = (
    spec("navigation.running", "bool",
         doc="the robot has a navigation goal it has neither reached nor given up on "
             "(driving, turning on the goal, paused or blocked)"),
    spec("navigation.arrived", "bool", doc="the last navigation goal was reached"),
    spec("navigation.blocked", "bool",
         doc="the way is blocked now (the robot waits, then plans around it)"),
    spec("navigation.blocked_for", "float", "s", (0.0, 1e9),
         "seconds the way has been blocked; 0 when it is not"),
    spec("navigation.failed", "bool", doc="the last navigation goal failed (see navigation.failure)"),
    spec("navigation.failure", "str",
         doc="why the last navigation goal failed; absent unless it failed",
         values=FAILURES),
    spec("guide.arrived", "bool",
         doc="the guide reached its place with the user and announced the arrival"),
    spec("guide.user_lost", "bool",
         doc="the guide gave up: the user did not follow within the time allowed"),
    spec("guide.user_distance", "float", "m", (0.0, 30.0),
         "distance from the robot's centre to the person following it; absent when not seen "
         "for 1 s or when not guiding"),
    spec("guide.waiting", "bool",
         doc="the guide has stopped because the user fell behind, and asks them to follow"),
    spec("robot.at_home", "bool",
         doc="the robot stands within 0.3 m of the map's robot_home place"),
)


def read(ctx: PerceptContext) -> dict:
    values: dict = {}
    nav = ctx.skills.blackboard.value("navigation/state")
    if nav is not None:
        values.update({
            "navigation.running": nav.phase in RUNNING_PHASES,
            "navigation.arrived": nav.phase == ARRIVED,
            "navigation.blocked": nav.phase == BLOCKED,
            "navigation.blocked_for": float(nav.blocked_for) if nav.phase == BLOCKED else 0.0,
            "navigation.failed": nav.phase == FAILED,
            "navigation.failure": nav.failure if nav.phase == FAILED and nav.failure else None,
        })
    guide = ctx.skills.blackboard.value("guide/state")
    if guide is not None:
        values.update({
            "guide.arrived": guide.phase == GUIDE_ARRIVED,
            "guide.user_lost": guide.phase == GAVE_UP and guide.outcome == OUTCOME_USER_LOST,
            "guide.user_distance": (guide.user_distance if guide.phase not in (
                GUIDE_ARRIVED, GAVE_UP) else None),
            "guide.waiting": guide.phase == WAITING,
        })
    grid = getattr(ctx.skills, "map", None)
    pose = ctx.fresh("robot/pose")
    if grid is not None and pose is not None and HOME in grid.places:
        home = grid.places[HOME]
        values["robot.at_home"] = math.hypot(pose[0] - home[0], pose[1] - home[1]) <= AT_HOME
    return values


NAVIGATION = PerceptProvider("navigation", SPECS, read)
