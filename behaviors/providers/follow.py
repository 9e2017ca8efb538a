"""The following percepts: how far the customer is, whether they are lost, what the robot does.

Read from `following/state` (skills/following/). Absent while the robot follows nobody; while
following, `follow.distance` is absent when the customer is not seen.
"""
from __future__ import annotations

from behaviors.percepts import PerceptContext, PerceptProvider, spec
from skills.following import PHASES

SPECS = (
    spec("follow.active", "bool", doc="the robot is following a customer (also while searching)"),
    spec("follow.distance", "float", "m", (0.0, 30.0),
         "distance from the robot's centre to the followed customer; absent when unseen"),
    spec("follow.error", "float", "m", (0.0, 30.0),
         "how far the distance is off the following distance (absolute); absent when unseen"),
    spec("follow.lost", "bool",
         doc="the followed customer is not seen (hidden, searched for, or given up on)"),
    spec("follow.lost_for", "float", "s", (0.0, 1e9),
         "seconds the customer has been unseen; 0 while seen"),
    spec("follow.searching", "bool",
         doc="the robot searches for the customer: drives to where they were, turns, calls"),
    spec("follow.waiting", "bool", doc="the customer stands and the robot waits behind them"),
    spec("follow.waiting_for", "float", "s", (0.0, 1e9),
         "seconds the customer has been standing with the robot waiting; 0 while they walk"),
    spec("follow.gave_up", "bool", doc="the robot gave up finding the customer"),
    spec("follow.reacquired", "int", None, (0, 1000),
         "times the customer was found again after being hidden, since following began"),
    spec("follow.phase", "str", doc="what the follower does", values=PHASES),
)


def read(ctx: PerceptContext) -> dict:
    state = ctx.fresh("following/state")
    if state is None:
        return {}
    active = state.phase not in ("idle", "gave_up")
    values = {
        "follow.active": active,
        "follow.lost": state.lost,
        "follow.lost_for": float(state.lost_for),
        "follow.searching": state.phase == "searching",
        "follow.waiting": state.phase == "waiting",
        "follow.waiting_for": float(state.waiting_for),
        "follow.gave_up": state.phase == "gave_up",
        "follow.reacquired": state.reacquisitions,
        "follow.phase": state.phase,
    }
    if active and state.distance is not None:
        values["follow.distance"] = float(state.distance)
        values["follow.error"] = abs(float(state.distance) - state.setpoint)
    return values


FOLLOW = PerceptProvider("follow", SPECS, read)
