"""Backing out of a wedge: a box-shaped base whose wanted turn the room for its corners holds
at zero (a cart against its side, a shelf at a corner) and that cannot drive on either.

The safety arbiter stops a turn that would sweep a corner into something (`safety.
turn_rate_within`), and the way ahead may be blocked too; then no goal gets the robot out:
HOROS stood 30 s with a shopper's cart against its front corner and side, asked to turn by
the follower's search and by navigation (bench_follow crowd10 seed 8, issue 23). A person
in its place steps back before turning. So: once a wanted turn has been held at zero, with
the robot not driving forward, for WEDGED_AFTER s, the robot backs straight out at
BACK_OUT_SPEED until that turn has TURN_FREED of room, or BACK_OUT_MAX is backed, or the
goal no longer asks to turn. One back-out a wedge: if the turn is still held after it, the
robot stands (it does not back down a hallway 0.6 m at a time) until the turn has been free or
the goal stopped asking to turn. Backing passes the arbiter like any command (its rear check
stops it before anything behind); it starts only with the arbiter's stop distance behind
free, plus a margin. A round base sweeps nothing: it is never wedged by its corners.
"""
from __future__ import annotations

import math

from skills.safety import STOP_DISTANCE

WEDGED_AFTER = 2.0                 # s a wanted turn is held at zero before backing out
HELD = math.radians(2)             # rad of room below which the turn is held
TURN_FREED = math.radians(15)      # rad of room for the wanted turn that ends the backing
BACK_OUT_SPEED = 0.15              # m/s backwards
BACK_OUT_MAX = 0.6                 # m backed out at most, a wedge at a time
REAR_MARGIN = 0.1                  # m free behind beyond the arbiter's stop distance to start
CREEPING = 0.02                    # m/s: a wanted forward speed below this is standing


class WedgeRecovery:
    """The wanted velocity, or a straight back-out while the base is wedged (see the module)."""

    def __init__(self) -> None:
        self._held_since: float | None = None
        self._backing_from: tuple[float, float] | None = None
        self._spent = False          # backed out of this wedge already, still held

    def command(self, v: float, w: float, room: tuple[float, float], free_ahead: float,
                free_behind: float, x: float, y: float, now: float
                ) -> tuple[float, float, str]:
        """(v, w) to send to the arbiter and why it is not the wanted one ('' when it is).
        `room` (left, right) rad the body may turn; `free_ahead`/`free_behind` m; (x, y) the
        robot's position."""
        wanted_room = room[0] if w > 0.0 else room[1] if w < 0.0 else math.inf
        if self._backing_from is not None:
            backed = math.hypot(x - self._backing_from[0], y - self._backing_from[1])
            if (w == 0.0 or wanted_room >= TURN_FREED or backed >= BACK_OUT_MAX
                    or free_behind < STOP_DISTANCE):
                self._backing_from = self._held_since = None
                self._spent = w != 0.0 and wanted_room < HELD
                return v, w, ""
            return -BACK_OUT_SPEED, 0.0, f"backing out of a wedge to turn ({backed:.2f} m)"
        driving_on = v > CREEPING and free_ahead >= STOP_DISTANCE
        if w == 0.0 or wanted_room >= HELD or driving_on:
            self._held_since, self._spent = None, False
            return v, w, ""
        if self._spent:
            return v, w, ""
        if self._held_since is None:
            self._held_since = now
        if (now - self._held_since >= WEDGED_AFTER - 1e-9
                and free_behind >= STOP_DISTANCE + REAR_MARGIN):
            self._backing_from = (x, y)
            return -BACK_OUT_SPEED, 0.0, "backing out of a wedge to turn (0.00 m)"
        return v, w, ""
