"""Keeping the distance: drive behind the customer while she walks, wait near her while she
stands, and give way to anybody who walks at the robot.

- **following**: the robot drives (through the navigation skill, so around shelves and other
  shoppers) towards the customer, led by her velocity so it does not trail, at a pace that
  matches hers plus a correction for the distance error; walking, it keeps beyond `distance`
  what of its stopping distance exceeds `tolerance` (a dead stop of hers ends no further than
  that inside `distance`), and no more: it is barely faster than her. Never closer than
  `min_distance`: the safety arbiter refuses to drive at anybody inside it while following,
  and anybody (the customer too) walking at the robot inside it makes it back off
  (`skills.giving_way`); somebody whose course passes the robot's body by (`_walking_at`) is
  passing, not walking at it.
- **asking to pass**: while somebody else stands in its way (navigation blocked by a
  person for `ASK_AFTER` s), the robot asks them to let it pass (`excuse`), at most once
  every `ASK_EVERY` s (in a crowd the way is blocked and clear by turns): people who crossed
  its way have passed by then, and a shopper standing at a shelf with her cart across the
  aisle, or waiting for the robot to move while it waits for her, does not otherwise know
  she is in the way.
- **waiting**: she stands (or comes closer) within reach: the robot faces her and closes in
  slowly to half its stopping distance inside `distance` (backing off to it, where it can see
  behind, when a search left it closer).

A part of `Following` (`skills.following.follower`); it reads `params`, `motion`,
`navigation`, `perception` and her pace (`skills.following.identity`).
"""
from __future__ import annotations

import math

from skills import giving_way
from skills.motion import Goal
from skills.people.track import CONFIRMED

BRAKE = 0.8               # share of the base's max_accel counted on for stopping
LATENCY_MARGIN = 0.1      # m covered before a stop command takes effect (a tick or two)
CREEP = 0.2               # m/s at most, closing in on a customer who stands
PASS_HORIZON = 1.5        # s a person's course is run on to see whether it meets the robot
ASK_AFTER = 3.0           # s blocked by a person before asking them to let the robot pass
ASK_EVERY = 10.0          # s between two asks while the way stays blocked
ASK_NEAR = 1.3            # m from what blocks the way to a person who is asked: a shopper's
                          # cart reaches 1.2 m ahead of her, and it is the cart that blocks
PASS_CLEAR = 0.6          # m, centre to centre: a course that stays this far off passes the
                          # robot by (its 0.26 m radius, a person's 0.25 m and 0.1 m)


class Keeping:
    """Driving behind, waiting near, giving way (a part of `Following`)."""

    def _give_way(self, robot, now: float) -> None:
        """Anybody (the customer too) walking at the robot inside `min_distance` makes it
        back off, facing them (`skills.giving_way`); whatever the phase wanted waits. Only
        those whose course meets the robot count: a crosser walking past it inside the
        minimum, partly towards it, made it back off and drop its way (crowd20, issue 23)."""
        seen = [t for t in self.perception.believed
                if t.status == CONFIRMED and _walking_at(t, robot)]
        intruder = giving_way.closing_in(seen, robot, self.params.min_distance)
        if intruder is None:
            return
        self._hold(now)
        self.motion.start(giving_way.back_off(intruder, robot), now)

    def _ask_to_pass(self, now: float) -> None:
        """Somebody other than her has stood in the robot's way for `ASK_AFTER` s: ask them
        to let it pass (not while the robot is speaking, nor within `ASK_EVERY` s of the last
        ask)."""
        nav = self.navigation
        if nav is None or self.speech is None:
            return
        if nav.state.phase != "blocked":
            return
        if nav.state.blocked_for < ASK_AFTER or self.speech.status.running:
            return
        if self._asked_at is not None and now - self._asked_at < ASK_EVERY:
            return
        her = frozenset() if self.state.target is None else frozenset({self.state.target})
        if nav.person_blocking(ASK_NEAR, ignore=her) is None:
            return
        self._asked_at = now
        self.speech.say(self.params.excuse, now)

    def _drive_behind(self, track, robot, d: float, now: float) -> None:
        """Drive towards the customer (led a little by their velocity) at their pace plus the
        distance error times the gain, which keeps `distance`."""
        p = self.params
        tx, ty = track.x + track.vx * p.lead_time, track.y + track.vy * p.lead_time
        dx, dy = tx - robot[0], ty - robot[1]
        lead = math.hypot(dx, dy)
        if lead <= p.min_distance + 0.05:
            self._face(track.x, track.y, robot, now)
            return
        # The goal is the customer (led by their velocity): the path must reach beyond the
        # point to keep for the local controller to drive at the pace asked; the pace keeps the
        # distance, and the robot stops at `min_distance` at the latest (waiting, above).
        gx, gy = tx, ty
        if not self._free(gx, gy):
            goal = self._nearest_free(gx, gy) or self._on_trail(track.x, track.y)
            if goal is None:
                self._face(track.x, track.y, robot, now)
                return
            gx, gy = goal
        pace = self._pace(track, now)
        brake = BRAKE * self.motion.limits.max_accel
        # walking, keep beyond the setpoint what of the stopping distance exceeds the
        # tolerance: should the customer stop dead, the robot comes to rest no further inside
        # it than the tolerance, and walks as close to the setpoint as that allows (a robot
        # barely faster than her catches up slowly, so every cm it trails counts)
        error = d - (p.distance + max(self._stopping_distance(pace) - p.tolerance, 0.0))
        gain = p.speed_gain if error >= 0 else 2 * p.speed_gain     # closing in: brake harder
        speed = pace + gain * error
        # never faster than what still stops at min_distance should the customer stop dead
        speed = min(speed, math.sqrt(2 * brake * max(d - p.min_distance - LATENCY_MARGIN, 0.0)))
        self._drive_to((gx, gy), speed, now)

    def _wait_near(self, track, robot, d: float, pace: float, now: float) -> None:
        """She stands: face her, and close in slowly to half the stopping distance at her
        usual pace inside the setpoint (0.99 m for 1.2 m at 0.5 m/s). When she walks off, the
        robot needs about a second to reach her pace and falls that much behind: waiting at
        the setpoint it would trail her 0.4 m beyond it for several seconds; from here the lag
        ends about as far outside as it began inside. Never while she comes closer; when
        the robot is well inside that (after a search), it backs off to it."""
        p = self.params
        near = max(p.distance - self._stopping_distance(self._usual_pace) / 2,
                   p.min_distance + 0.1)
        if d > near + 0.1 and pace < p.standing and not _approaching(track, robot):
            self._drive_to((track.x, track.y), min(CREEP, p.speed_gain * (d - near)), now)
        elif d < near - 0.15 and pace < p.standing:
            # too close (a search that ended next to her): back off, facing her, where the
            # robot can see behind it (the safety arbiter stops it otherwise)
            self._hold(now)
            self.motion.start(Goal("back_off", bearing=math.atan2(track.y - robot[1],
                                                                  track.x - robot[0]),
                                   speed=min(CREEP / 2, p.speed_gain * (near - d))), now)
        elif d < p.min_distance:
            # inside the minimum, walking on at it slowly: stand still, no turning on the spot
            # (a turn of a few degrees to face her while she pressed against the robot counted
            # as the robot moving into her, on HOROS in tests/skills/test_giving_way.py)
            self._hold(now)
            if self.motion.goal is not None and self.motion.goal.kind == "turn_to":
                self.motion.cancel(now)
        else:
            self._face(track.x, track.y, robot, now)

    def _stopping_distance(self, pace: float) -> float:
        """m the robot needs to stop from `pace` (braking at BRAKE of max_accel, plus what it
        covers before the stop takes effect)."""
        brake = BRAKE * self.motion.limits.max_accel
        return pace * pace / (2 * brake) + LATENCY_MARGIN * pace / 0.5

    def _drive_to(self, goal, speed: float, now: float) -> None:
        nav = self.navigation
        if nav is None:
            return
        top = nav.limits.max_speed
        speed = min(max(speed, 0.05), top)
        # while its way is blocked (somebody standing in it, often waiting for the robot to
        # move), navigation keeps its goal: a new one would restart the wait each time, and
        # it plans round the blocker only after `replan_after` s
        blocked = nav.state.phase == "blocked"
        renew = (self._goal is None or nav.state.phase not in ("driving", "blocked")
                 or (not blocked and (math.hypot(goal[0] - self._goal[0], goal[1] - self._goal[1])
                                      > self.params.goal_step
                                      or now - self._goal_t >= self.params.goal_every)))
        if renew:
            self._goal, self._goal_t = goal, now
            nav.go_to(goal, now, speed=speed)
        else:
            nav.set_speed(speed)

    def _face(self, x: float, y: float, robot, now: float) -> None:
        self._hold(now)
        self.motion.start(Goal("turn_to", bearing=math.atan2(y - robot[1], x - robot[0])), now)

    def _hold(self, now: float) -> None:
        """Stop driving (drop the navigation goal, if ours)."""
        if self.navigation is not None and self.navigation.state.phase not in ("idle", "arrived",
                                                                                "failed"):
            self.navigation.cancel(now)
        self._goal = None


def _walking_at(track, robot) -> bool:
    """Whether the track's straight course over the next PASS_HORIZON s comes within
    PASS_CLEAR of the robot's centre (a passer-by's stays off it, however much of their
    velocity points at the robot on the way)."""
    rx, ry = track.x - robot[0], track.y - robot[1]
    v2 = track.vx * track.vx + track.vy * track.vy
    t = 0.0 if v2 == 0.0 else min(max(-(rx * track.vx + ry * track.vy) / v2, 0.0), PASS_HORIZON)
    return math.hypot(rx + track.vx * t, ry + track.vy * t) < PASS_CLEAR


def _approaching(track, robot) -> bool:
    dx, dy = robot[0] - track.x, robot[1] - track.y
    d = math.hypot(dx, dy)
    return d > 0.0 and (track.vx * dx + track.vy * dy) / d > 0.2
