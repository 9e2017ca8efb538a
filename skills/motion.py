"""Motion: turn towards the user, approach or keep a distance, turn to a bearing — with speed caps.

One goal at a time. Each tick `act` computes the wanted velocity for the goal, passes it
through the safety arbiter, and sends it to the base — zero when there is no goal, so the
driver always gets a fresh command and its watchdog never has to step in on a healthy loop.

A drive fault the base may reset (its `reset_faults` option, from the profile or `interbot run
--reset-faults`, and the controller no longer reporting the cause: `extra["fault_resettable"]`)
is reset here, and only while the application asks for no motion (no goal: its fault branch's
behavior stands still); the base then holds zero until a goal commands anew. A `fault_reset`
event says so.

A "navigate" goal hands the velocity to the navigation skill (`navigator`), which computes it
each tick; it still passes the safety arbiter here like every other command.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from robots.base import Base
from robots.exceptions import FaultResetError
from robots.profile import Limits
from skills.perception import PeoplePerception
from skills.localization import Localization
from skills.navigation.footprint import Footprint, corner_reach, turn_room
from skills.safety import LEFT_BEHIND, PERSON_MIN_DISTANCE, TURN_MARGIN, arbitrate
from skills.skill import Skill
from skills.status import IDLE, RUNNING, SUCCEEDED, failed
from skills.wedge import WedgeRecovery

TURN_GAIN = 1.5            # rad/s per rad of heading error
DISTANCE_GAIN = 0.8        # m/s per m of distance error
ALIGNED = math.radians(6)  # heading error counted as "facing"
AT_DISTANCE = 0.1          # m
PERSON_BODY_RADIUS = 0.2   # m: a tracked person's body, for the room to turn
PERSON_CONE = math.radians(60)   # a person this far off the heading (or its reverse) is
                                 # ahead (behind) for the arbiter's minimum distance


@dataclass(frozen=True)
class Goal:
    kind: str                 # "face_user", "keep_distance", "turn_to", "navigate", "back_off"
    distance: float = 1.0     # keep_distance: wanted distance to the user, m
    bearing: float = 0.0      # turn_to, back_off: world heading to face, rad
    speed: float = 0.0        # back_off: m/s backwards (the arbiter stops it before anything
                              # behind, and on a robot with no sensor behind)


def wrap(angle: float) -> float:
    """Angle in (-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))


class Motion(Skill):
    name = "motion"

    def __init__(self, blackboard, events, base: Base, limits: Limits,
                 localization: Localization, perception: PeoplePerception,
                 footprint: Footprint | None = None) -> None:
        super().__init__(blackboard, events)
        self.base = base
        # the body whose corners a turn sweeps (a round one sweeps nothing)
        self.footprint = footprint or Footprint.round(0.0)
        self.limits = limits
        self.localization = localization
        self.perception = perception
        self.goal: Goal | None = None
        self.navigator = None     # the navigation skill: its velocity(now) drives a "navigate" goal
        # the track a follower drives behind: not counted for the near-people cap while they
        # walk away from the robot (it would never keep up); counted again when they come back
        self.followed: int | None = None
        # inside this (m, centre to centre) the arbiter never drives towards anybody; the
        # follower sets its own minimum while it follows
        self.min_person_distance = PERSON_MIN_DISTANCE
        self.wedge = WedgeRecovery()     # backs a box-shaped base out when it cannot turn

    def start(self, goal: Goal, now: float) -> None:
        self.goal = goal
        self.set_status(RUNNING, now)

    def cancel(self, now: float) -> None:
        self.goal = None
        self.set_status(IDLE, now)

    def act(self, now: float) -> None:
        self._reset_fault_while_still(now)
        v, w = self._wanted(now)
        link = self.blackboard.value("robot/link", False)
        free = self.blackboard.value("obstacles/front", math.inf)
        behind = self.blackboard.value("obstacles/rear", 0.0)      # unknown: not free
        room = self._turn_room() if w else (math.inf, math.inf)
        v, w, wedged = self._unwedged(v, w, room, free, behind, now)
        if wedged:
            room = (math.inf, math.inf)                             # backing straight out
        ahead, rear = self._people_ahead_and_behind()
        v, w, reason = arbitrate(v, w, link_fresh=link, free_ahead=free, free_behind=behind,
                                 nearest_person=self._nearest_person(v), limits=self.limits,
                                 person_ahead=ahead, person_behind=rear,
                                 min_person_distance=self.min_person_distance,
                                 turn_room=room)
        self.base.command(v, w)
        self.write("motion/command", (v, w), now)
        self.write("motion/limit", reason or wedged, now)

    def _unwedged(self, v: float, w: float, room, free: float, behind: float, now: float):
        """The wanted (v, w), or the wedge recovery's back-out (`skills.wedge`) and why."""
        state = self.localization.state
        if self.footprint.is_round or state is None:
            return v, w, ""
        return self.wedge.command(v, w, room, free, behind, state.x, state.y, now)

    def _turn_room(self) -> tuple[float, float]:
        """rad the body may turn each way: the sensed readings' room, and each tracked
        person's as a body of PERSON_BODY_RADIUS (beside or behind a robot whose laser looks
        ahead only, a track may be all it knows of someone)."""
        left, right = self.blackboard.value("obstacles/turn_room", (math.inf, math.inf))
        state = self.localization.state
        if self.footprint.is_round or state is None or not self.perception.tracks:
            return left, right
        # only someone within a corner's reach can be swept (turn_room would drop the rest)
        reach = corner_reach(self.footprint, PERSON_BODY_RADIUS, TURN_MARGIN)
        near = [t for t in self.perception.tracks
                if (t.x - state.x) ** 2 + (t.y - state.y) ** 2 < reach * reach]
        if not near:
            return left, right
        c, s = math.cos(state.th), math.sin(state.th)
        people = [(c * (t.x - state.x) + s * (t.y - state.y),
                   -s * (t.x - state.x) + c * (t.y - state.y)) for t in near]
        by_people = turn_room(self.footprint, people, PERSON_BODY_RADIUS, TURN_MARGIN)
        return min(left, by_people[0]), min(right, by_people[1])

    def _reset_fault_while_still(self, now: float) -> None:
        """Reset a drive fault the base offers to reset, while no goal asks for motion."""
        state = self.localization.odometry
        if state is None or self.goal is not None or not state.extra.get("fault_resettable"):
            return
        device = state.extra.get("fault_device")
        try:
            reset = self.base.reset_faults()
        except FaultResetError as exc:
            self.events.emit(now, "fault_reset", device=device, sent=False, reason=str(exc))
            return
        if reset:
            self.events.emit(now, "fault_reset", device=device, sent=True,
                             reason=state.extra.get("fault_meaning", ""))

    def stop_now(self, now: float) -> None:
        """Drop the goal and send zero at once (faults, shutdown)."""
        self.goal = None
        self.base.stop()
        self.write("motion/command", (0.0, 0.0), now)

    def _wanted(self, now: float) -> tuple[float, float]:
        goal, state = self.goal, self.localization.state
        if goal is None or state is None:
            return 0.0, 0.0
        if goal.kind == "navigate":
            return self.navigator.velocity(now) if self.navigator is not None else (0.0, 0.0)
        if goal.kind == "turn_to":
            return 0.0, self._turn(goal.bearing - state.th, now, done_when_aligned=True)
        if goal.kind == "back_off":
            return -abs(goal.speed), self._turn(goal.bearing - state.th, now,
                                                done_when_aligned=False)
        user = self.perception.user
        if user is None:
            self.set_status(failed("no user to face"), now)
            return 0.0, 0.0
        dx, dy = user.x - state.x, user.y - state.y
        w = self._turn(math.atan2(dy, dx) - state.th, now, done_when_aligned=goal.kind == "face_user")
        if goal.kind == "keep_distance":
            error = math.hypot(dx, dy) - goal.distance
            v = DISTANCE_GAIN * error if abs(error) > AT_DISTANCE else 0.0
            facing = abs(wrap(math.atan2(dy, dx) - state.th)) < 4 * ALIGNED
            self.set_status(SUCCEEDED if abs(error) <= AT_DISTANCE and facing else RUNNING, now)
            return (v if facing else 0.0), w
        return 0.0, w

    def _turn(self, error: float, now: float, done_when_aligned: bool) -> float:
        error = wrap(error)
        if done_when_aligned:
            self.set_status(SUCCEEDED if abs(error) < ALIGNED else RUNNING, now)
        return TURN_GAIN * error if abs(error) >= ALIGNED / 2 else 0.0

    def top_speed(self) -> float:
        """m/s: the fastest the arbiter lets the robot drive forward now: the profile's
        `max_speed_near_people` while someone the near-people cap is for is within
        `near_people_distance`, else its `max_speed`. A follower among shoppers may drive no
        faster than the cap, whatever its top speed on an empty floor."""
        limits = self.limits
        if self._nearest_person(1.0) < limits.near_people_distance:
            return min(limits.max_speed, limits.max_speed_near_people)
        return limits.max_speed

    def _nearest_person(self, v: float = 0.0) -> float:
        """m to the nearest person the near-people cap is for: not one the robot leaves
        behind (more than LEFT_BEHIND off the way it drives: driving on can only widen that
        gap, and slowing down would let them close in), nor a receding followed customer."""
        state = self.localization.state
        if state is None or not self.perception.tracks:
            return math.inf
        way = state.th if v >= 0 else state.th + math.pi
        return min((math.hypot(t.x - state.x, t.y - state.y) for t in self.perception.tracks
                    if not self._receding_followed(t, state)
                    and (v == 0 or abs(wrap(math.atan2(t.y - state.y, t.x - state.x) - way))
                         <= LEFT_BEHIND)), default=math.inf)

    def _people_ahead_and_behind(self) -> tuple[float, float]:
        """m to the nearest tracked person within ±60° of the heading, and of the reverse
        heading (anybody beside the robot is passed, not driven at)."""
        state = self.localization.state
        ahead = behind = math.inf
        if state is None:
            return ahead, behind
        for track in self.perception.tracks:
            dx, dy = track.x - state.x, track.y - state.y
            d = math.hypot(dx, dy)
            bearing = abs(wrap(math.atan2(dy, dx) - state.th))
            if bearing <= PERSON_CONE:
                ahead = min(ahead, d)
            elif bearing >= math.pi - PERSON_CONE:
                behind = min(behind, d)
        return ahead, behind

    def _receding_followed(self, track, state) -> bool:
        """The followed customer while not walking towards the robot (approach ≤ 0.1 m/s)."""
        if self.followed is None or track.id != self.followed:
            return False
        dx, dy = state.x - track.x, state.y - track.y
        d = math.hypot(dx, dy)
        return d > 0.0 and (track.vx * dx + track.vy * dy) / d <= 0.1
