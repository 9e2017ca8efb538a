"""Giving way: somebody walking at the robot inside its minimum distance makes it back off.

A robot among shoppers must never push anyone. The safety arbiter (`skills.safety`) already
keeps it from driving at a person inside the minimum distance; this is the other half: when
someone (the customer too) comes closer than that and keeps coming, the robot backs away from
them, facing them, at their closing speed plus a margin. Backing up passes the arbiter's rear
check like any other backward motion: with no free space (or no sensor) behind, the robot
stands, facing them, and still never moves towards them.
"""
from __future__ import annotations

import math

from skills.motion import Goal

CLOSING = 0.25           # m/s towards the robot above which a person is closing in (a standing
                         # track's velocity noise is about 0.1 m/s)
MARGIN = 0.1             # m/s faster than they close in
MAX_BACK_OFF = 0.3       # m/s


def closing_speed(track, robot) -> float:
    """m/s at which the track walks towards the robot's centre (negative: away)."""
    dx, dy = robot[0] - track.x, robot[1] - track.y
    d = math.hypot(dx, dy)
    return (track.vx * dx + track.vy * dy) / d if d > 0.0 else 0.0


def closing_in(tracks, robot, min_distance: float):
    """The nearest track inside `min_distance` (centre to centre) that walks towards the robot
    faster than CLOSING, or None."""
    near = [(math.hypot(t.x - robot[0], t.y - robot[1]), t) for t in tracks
            if math.hypot(t.x - robot[0], t.y - robot[1]) < min_distance
            and closing_speed(t, robot) > CLOSING]
    return min(near, key=lambda pair: pair[0])[1] if near else None


def back_off(track, robot) -> Goal:
    """Back away from the track, turning to face it, a little faster than it closes in."""
    bearing = math.atan2(track.y - robot[1], track.x - robot[0])
    speed = min(closing_speed(track, robot) + MARGIN, MAX_BACK_OFF)
    return Goal("back_off", bearing=bearing, speed=speed)


__all__ = ["closing_in", "closing_speed", "back_off", "CLOSING"]
