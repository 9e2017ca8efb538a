"""The safety arbiter: the last word on every motion command before it reaches the base.

It refuses to move on stale or missing base data, stops forward motion before an obstacle
ahead and backward motion before one behind (or where no sensor looks), never drives towards a
person inside the minimum distance (forward at someone ahead, backward at someone behind),
slows a turn that would sweep a box-shaped body's corner into something beside it, and caps
speed near people. It only ever reduces a command, never adds motion.
"""
from __future__ import annotations

import math

from robots.profile import Limits

STOP_DISTANCE = 0.30        # m of free space ahead (behind) below which forward (backward)
                            # motion stops
PERSON_MIN_DISTANCE = 0.6   # m, robot centre to a person's, inside which the robot never
                            # drives towards them (a follower sets its own minimum)
SLOW_STOP = 0.10            # m: driving forward slowly, the free space needed beyond braking
TURN_MARGIN = 0.05          # m a turning corner keeps from anything (skills.obstacles' readings,
                            # motion's tracked people)
TURN_LAG = 0.1              # s a turn goes on at the commanded rate before braking begins (a
                            # tick and the base's answer)
LEFT_BEHIND = math.radians(100)  # a person farther than this off the way the robot drives
                            # is left behind: driving on only widens the gap, so the
                            # near-people speed cap (controller and arbiter) is not for them


def stop_distance(v: float, limits: Limits) -> float:
    """The free space ahead forward motion at `v` m/s needs: its braking distance plus
    SLOW_STOP, at most STOP_DISTANCE. Creeping through a narrow door, the jamb beside the front
    corner is nearer than STOP_DISTANCE and no danger at that speed."""
    return min(STOP_DISTANCE, SLOW_STOP + v * v / (2 * limits.max_accel))


def turn_rate_within(room: float, limits: Limits) -> float:
    """The fastest turn (rad/s) that stops within `room` rad: TURN_LAG at that rate, then
    braking at the base's turn acceleration."""
    if room <= 0.0:
        return 0.0
    a = limits.max_turn_accel
    return a * (math.sqrt(TURN_LAG * TURN_LAG + 2.0 * room / a) - TURN_LAG)


def arbitrate(v: float, w: float, *, link_fresh: bool, free_ahead: float, free_behind: float,
              nearest_person: float, limits: Limits, person_ahead: float = math.inf,
              person_behind: float = math.inf,
              min_person_distance: float = PERSON_MIN_DISTANCE,
              turn_room: tuple[float, float] = (math.inf, math.inf)) -> tuple[float, float, str]:
    """Return the safe (v, w) and the reason it was reduced ('' when unchanged).
    `person_ahead` / `person_behind`: m to the nearest person in front of / behind the robot
    (robot centre to theirs). `turn_room`: rad the body may turn left / right before a corner
    nears something (`skills.navigation.footprint.turn_room`)."""
    if not (math.isfinite(v) and math.isfinite(w)):
        return 0.0, 0.0, "command was not a finite number"
    if not link_fresh:
        return 0.0, 0.0, "base data is stale or the link is down"
    reason = ""
    if v > 0 and free_ahead < stop_distance(v, limits):
        v, reason = 0.0, f"obstacle {free_ahead:.2f} m ahead"
    if v < 0 and free_behind < STOP_DISTANCE:
        v, reason = 0.0, f"obstacle {free_behind:.2f} m behind (or no sensor there)"
    if v > 0 and person_ahead < min_person_distance:
        v, reason = 0.0, (f"person {person_ahead:.2f} m ahead, inside the minimum "
                          f"{min_person_distance:.2f} m")
    if v < 0 and person_behind < min_person_distance:
        v, reason = 0.0, (f"person {person_behind:.2f} m behind, inside the minimum "
                          f"{min_person_distance:.2f} m")
    side, room = ("left", turn_room[0]) if w > 0 else ("right", turn_room[1])
    allowed = turn_rate_within(room, limits) if w != 0 else math.inf
    if abs(w) > allowed:
        w = math.copysign(allowed, w)
        reason = reason or (f"turning {side} would sweep a corner into something "
                            f"{math.degrees(room):.0f} deg on")
    if nearest_person < limits.near_people_distance and abs(v) > limits.max_speed_near_people:
        v = math.copysign(limits.max_speed_near_people, v)
        reason = reason or f"person within {limits.near_people_distance} m"
    if abs(v) > limits.max_speed:
        v, reason = math.copysign(limits.max_speed, v), reason or "speed limit"
    if abs(w) > limits.max_turn_rate:
        w, reason = math.copysign(limits.max_turn_rate, w), reason or "turn-rate limit"
    return v, w, reason
