"""Following a customer: keep one tracked person at a distance, find them again after a loss.

`follow(target, now)` picks the customer (a track id, else the user) and from then on, each tick:

- **following** / **waiting**: the customer is seen, walking / standing: keep the distance
  (`skills.following.keeping`).
- **hidden** / **searching**: her track is not seen: go where she should be, then search
  round it and call (`skills.following.searching`).
- **gave up**: not found for `give_up_after` s: the skill fails with a reason saying where it
  last saw her and for how long it searched.

Which track is her each tick is `skills.following.identity`'s; where the robot fits,
`skills.following.room`'s. Whatever the phase, anybody walking at the robot inside
`min_distance` makes it back off (`Keeping._give_way`). This module is the phase machine that
ties the parts together.

Typed status: running ('' following, 'waiting', 'hidden for N s', 'searching for N s'),
failed (`NO_CUSTOMER`, `GAVE_UP` as the reason's first words), idle after `cancel`.
`following/state` (a `FollowState`) carries the same as values for the percepts.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from skills.following.identity import Identity, _Belief
from skills.following.keeping import Keeping, _approaching
from skills.following.pace import PaceWatch
from skills.following.room import Room
from skills.following.searching import Searching
from skills.localization import Localization
from skills.motion import Motion
from skills.navigation.navigation import EXCUSE
from skills.perception import PeoplePerception
from skills.safety import PERSON_MIN_DISTANCE
from skills.skill import Skill
from skills.status import IDLE, SkillStatus, Status, failed

# phases (FollowState.phase)
IDLE_PHASE = "idle"
FOLLOWING = "following"
WAITING = "waiting"
HIDDEN = "hidden"
SEARCHING = "searching"
GAVE_UP = "gave_up"
PHASES = (IDLE_PHASE, FOLLOWING, WAITING, HIDDEN, SEARCHING, GAVE_UP)

# failure codes: the first words of a failed status's reason
NO_CUSTOMER = "no customer"
GAVE_UP_REASON = "customer lost"

CALL = "Where are you? I cannot see you any more."
UNSURE = "I am not sure which of you I am following. Please wait a moment."
USUAL_PACE = 0.5          # m/s a customer walks at, until her own pace is known ...
PACE_LEARNING = 0.05      # ... from a running average of her pace while walking


@dataclass(frozen=True)
class FollowParams:
    distance: float = 1.2          # m, robot centre to customer centre
    min_distance: float = 0.8      # m: never drives closer than this
    tolerance: float = 0.3         # m the distance may fall short of `distance` when she stops
                                   # dead (the robot walks this much less of its stopping
                                   # distance beyond `distance`)
    lead_time: float = 0.6         # s: the goal runs ahead by the customer's velocity times this
    speed_gain: float = 0.8        # m/s per m of distance error, on top of the customer's speed
    standing: float = 0.2          # m/s: a slower customer counts as standing
    goal_step: float = 0.25        # m the goal must move before navigation gets the new one
    goal_every: float = 1.0        # s after which the goal is renewed anyway
    search_after: float = 4.0      # s hidden before the robot searches (drives, turns, calls)
    call_every: float = 8.0        # s between two calls while searching
    give_up_after: float = 30.0    # s unseen before giving up
    predict_for: float = 2.0       # s: the prediction runs on the velocity this long, then stands
    gate: float = 0.8              # m: the re-acquisition gate right after the loss ...
    gate_growth: float = 1.0       # m/s: ... grows at walking pace ...
    max_gate: float = 12.0         # m: ... up to this (a search reaches that far)
    jump: float = 1.5              # m: the target track this far off the prediction is a swap
    call: str = CALL
    excuse: str = EXCUSE           # said to somebody standing in the robot's way


@dataclass(frozen=True)
class FollowState:
    """What the follower is doing, as values (`following/state`)."""
    phase: str = IDLE_PHASE
    target: int | None = None            # the customer's track id (changes on re-acquisition)
    distance: float | None = None        # m, robot centre to the customer (None when unseen)
    setpoint: float = 1.2                # m
    lost_for: float = 0.0                # s the customer has been unseen
    waiting_for: float = 0.0             # s the customer has stood while the robot waited
    predicted: tuple[float, float] | None = None   # where the customer is believed to be
    last_seen: tuple[float, float] | None = None   # where they were last seen
    reacquisitions: int = 0              # times the customer was found again after a loss
    losses: int = 0                      # times the customer was lost (hidden)
    calls: int = 0
    swaps: int = 0                       # times a swap of track ids was undone (see _untangle)
    reason: str = ""

    @property
    def lost(self) -> bool:
        return self.phase in (HIDDEN, SEARCHING, GAVE_UP)


class Following(Identity, Keeping, Searching, Room, Skill):
    name = "following"

    def __init__(self, blackboard, events, localization: Localization,
                 perception: PeoplePerception, motion: Motion, navigation=None,
                 speech=None, params: FollowParams = FollowParams()) -> None:
        super().__init__(blackboard, events)
        self.localization = localization
        self.perception = perception
        self.motion = motion
        self.navigation = navigation
        self.speech = speech
        self.params = params
        self.state = FollowState(setpoint=params.distance)
        self._belief: _Belief | None = None
        self._others: set[int] = set()
        self._shadowed: dict[int, float] = {}  # id: when it was found somebody's shadow
        # look-alikes seen apart from her, never her: id -> when it was taken for a stranger
        self._strangers: dict[int, float] = {}
        self._stranger_seen: dict[int, _Belief] = {}   # id: a stranger's last sighting
        self._lost_since: float | None = None
        self._last_call = -math.inf
        self._goal: tuple[float, float] | None = None
        self._goal_t = -math.inf
        self._search_turns = 0
        self._search_heading: float | None = None
        self._trail: list[tuple[float, float]] = []   # where the customer walked, every 0.3 m
        self._search_goal: tuple[float, float] | None = None
        self._plan = None                     # the search plan of this loss (searching.py)
        self._plan_index = 0
        self._searched: list[str] = []        # its places looked at so far
        self._viewed: dict[int, float] = {}   # s each place of the plan was in view (this round)
        self._view_t: float | None = None     # ... counted up to this time
        self._way = None                      # (search goal, nearest yet, since when)
        self._looking_since: float | None = None
        self._asked_at: float | None = None   # somebody in the way last asked to let it pass
        self._recent: list[tuple[float, float, float]] = []    # (t, x, y) seen, newest last
        self._waiting_since: float | None = None
        self._contest: _Belief | None = None          # the customer before someone came close
        self._contest_ids: set[int] = set()
        self._contest_others: dict[int, _Belief] = {}  # the others as they came close to her
        self._contest_views: dict[int, list[tuple[float, float]]] = {}   # id: (view t, score)
        self._unsettled = False       # a contest ended with two fitting alike: decided each tick
        self._first_seen: dict[int, tuple[float, float, float]] = {}   # id: (t, x, y)
        self._usual_pace = USUAL_PACE
        self._look: np.ndarray | None = None           # what the customer looks like ...
        self._looks = 0                                # ... from this many camera views
        self._look_t: float | None = None              # time of the newest view used
        self._views: list[tuple[float, float]] = []   # (t, appearance score) of her track's
        self._views_of: int | None = None              # ... views, and that track's id
        self._matched: _Belief | None = None           # her state at the last view like her
        self._matched_t = -math.inf                    # ... and its time
        self.ambiguous = False        # two candidates fit alike (skills.following.score)
        self._said_unsure = False     # said so in this loss
        self._pace_watch = PaceWatch()   # asks her to wait when she outpaces the robot

    # -- the API for behaviors -------------------------------------------------------------

    def follow(self, now: float, target: int | None = None, **params) -> SkillStatus:
        """Start following track `target` (default: the user, else the nearest person within
        2.5 m). Keyword arguments override `FollowParams` fields (distance=, min_distance=,
        give_up_after=, call=, …); a bad one raises ValueError naming the field and the range."""
        self.params = _checked(replace(FollowParams(), **params))
        self._reset()
        track = self._initial_target(target)
        if track is None:
            self.state = FollowState(setpoint=self.params.distance)
            why = (f"track {target} is not among the people tracked now" if target is not None
                   else "nobody is tracked within 2.5 m to follow")
            self._fail(NO_CUSTOMER, why, now)
            return self.status
        self._see(track, now)
        if track.appearance is not None:
            self._learn(track.appearance)
            self._look_t = track.appearance_t
        self._matched, self._matched_t = self._belief, now
        self.state = FollowState(FOLLOWING, track.id, setpoint=self.params.distance,
                                 last_seen=(track.x, track.y), predicted=(track.x, track.y))
        self.motion.followed = track.id
        self.motion.min_person_distance = self.params.min_distance
        if self.navigation is not None:
            self.navigation.ignore_people = frozenset({track.id})
        self.set_status(SkillStatus(Status.RUNNING), now)
        self._publish(now)
        return self.status

    def cancel(self, now: float) -> None:
        """Stop following and stand still."""
        active = self.state.phase in (FOLLOWING, WAITING, HIDDEN, SEARCHING)
        self._release(now, stop=active)
        self._reset()
        self.state = FollowState(setpoint=self.params.distance)
        self.set_status(IDLE, now)
        self._publish(now)

    @property
    def active(self) -> bool:
        return self.state.phase in (FOLLOWING, WAITING, HIDDEN, SEARCHING)

    # -- the tick --------------------------------------------------------------------------

    def sense(self, now: float) -> None:
        pose = self.localization.state
        if not self.active or pose is None:
            return
        robot = (pose.x, pose.y, pose.th)
        if getattr(self.localization, "lost", False):
            self._pose_lost(now)
            self._publish(now)
            return
        self._note_births(now)
        track = self._find_target(now)
        if track is not None:
            self._on_seen(track, robot, now)
        else:
            self._on_unseen(robot, now)
        if self.active:
            self._give_way(robot, now)
            self._ask_to_pass(now)
        self._publish(now)

    def _pose_lost(self, now: float) -> None:
        """Without a trustworthy pose every track is in the wrong place: stand still and take
        nobody for the customer; the give-up clock runs on."""
        self._hold(now)
        goal = self.motion.goal
        if goal is not None and goal.kind in ("turn_to", "back_off"):
            self.motion.cancel(now)
        if self._lost_since is None:
            self._lost_since = now
            self.state = replace(self.state, losses=self.state.losses + 1)
        lost_for = now - self._lost_since
        if lost_for >= self.params.give_up_after:
            self._fail(GAVE_UP_REASON, f"not seen for {lost_for:.0f} s; the robot's position "
                       "was lost (localization), so it could not search", now)
            return
        reason = f"{HIDDEN} for {int(lost_for)} s: localization lost, standing still"
        self.state = replace(self.state, phase=HIDDEN, distance=None, lost_for=lost_for,
                             waiting_for=0.0, reason=reason)
        self.set_status(SkillStatus(Status.RUNNING, reason), now)

    # -- seen ------------------------------------------------------------------------------

    def _on_seen(self, track, robot, now: float) -> None:
        p = self.params
        reacquired = self.state.lost
        self._others.discard(track.id)     # taken back by her look: whatever it was, it is her
        self._see(track, now)
        self._lost_since = None
        self._said_unsure = False
        self._search_heading = None
        self._search_goal = None
        self._search_turns = 0
        if self._plan is not None:
            # the search's goal is not hers: navigation holds a goal while its way is blocked
            # (`Keeping._drive_to`), so found again 1.7 m off she was "followed" for 50 s with
            # the search's goal 9 m away (crowd5 seed 2, issue 23)
            self._goal = None
        self._plan, self._plan_index, self._searched = None, 0, []
        self._looking_since = None
        d = math.hypot(track.x - robot[0], track.y - robot[1])
        speed = self._pace(track, now)
        self._say(self._pace_watch.seen(now, d - p.distance, min(speed, self._usual_pace),
                                        self.motion.top_speed()), now)
        if self.state.phase == WAITING:     # hysteresis: the tracks' velocity noise is ~0.1 m/s
            stay = d <= p.distance + 0.3 and (speed < 2 * p.standing
                                                or _approaching(track, robot))
        else:
            stay = d <= p.distance + 0.15 and (speed < p.standing or _approaching(track, robot))
        if d < p.min_distance or stay:
            phase = WAITING
            self._wait_near(track, robot, d, speed, now)
        else:
            phase = FOLLOWING
            if speed >= p.standing:
                self._usual_pace += PACE_LEARNING * (speed - self._usual_pace)
            self._drive_behind(track, robot, d, now)
        self.motion.followed = track.id
        self.motion.min_person_distance = self.params.min_distance
        if self.navigation is not None:
            self.navigation.ignore_people = frozenset({track.id})
        if phase != WAITING:
            self._waiting_since = None
        elif self._waiting_since is None:
            self._waiting_since = now
        waiting_for = 0.0 if self._waiting_since is None else now - self._waiting_since
        self.state = replace(self.state, phase=phase, target=track.id, distance=d, lost_for=0.0,
                             waiting_for=waiting_for,
                             predicted=(track.x, track.y), last_seen=(track.x, track.y),
                             reacquisitions=self.state.reacquisitions + int(reacquired),
                             reason="")
        self.set_status(SkillStatus(Status.RUNNING, "waiting" if phase == WAITING else ""), now)

    # -- unseen ----------------------------------------------------------------------------

    def _on_unseen(self, robot, now: float) -> None:
        p = self.params
        if self._lost_since is None:
            self._lost_since = self._belief.t
            self.state = replace(self.state, losses=self.state.losses + 1)
        lost_for = now - self._lost_since
        self._say(self._pace_watch.lost(now), now)
        seen = (self._belief.x, self._belief.y)
        predicted = self._free_towards(seen, self._where_she_should_be(now)) or seen
        self.motion.followed = None            # unseen: everybody near counts for the speed cap
        if lost_for >= p.give_up_after:
            seen = self.state.last_seen
            self.state = replace(self.state, distance=None, lost_for=lost_for, predicted=predicted)
            places = ", ".join(self._searched) or "nowhere yet"
            self._fail(GAVE_UP_REASON, f"not seen for {lost_for:.0f} s; last seen at "
                       f"({seen[0]:.1f}, {seen[1]:.1f}), searched {places} and called "
                       f"{self.state.calls} time(s)", now)
            return
        if self.ambiguous:
            phase = HIDDEN if lost_for < p.search_after else SEARCHING
            self._unsure(predicted, robot, now)
        elif lost_for < p.search_after:
            phase = HIDDEN
            self._approach_prediction(predicted, robot, now)
        else:
            phase = SEARCHING
            self._search(predicted, robot, now)
        reason = f"{phase} for {int(lost_for)} s" + (
            ": not sure who she is, two people fit alike" if self.ambiguous else "")
        self._waiting_since = None
        self.state = replace(self.state, phase=phase, distance=None, lost_for=lost_for,
                             waiting_for=0.0, predicted=predicted, reason=reason)
        self.set_status(SkillStatus(Status.RUNNING, reason), now)

    def _unsure(self, predicted, robot, now: float) -> None:
        """Two candidates fit her alike: stop, face where she should be, say so once, and
        wait until one of them scores clearly better (the give-up clock runs on)."""
        self._face(predicted[0], predicted[1], robot, now)
        if not self._said_unsure and self.speech is not None:
            self.speech.say(UNSURE, now)
            self._said_unsure = True

    def _say(self, words: str | None, now: float) -> None:
        if words and self.speech is not None:
            self.speech.say(words, now)

    # -- the end ---------------------------------------------------------------------------

    def _release(self, now: float, stop: bool) -> None:
        if stop:
            self._hold(now)
            goal = self.motion.goal
            if goal is not None and goal.kind in ("turn_to", "navigate", "back_off"):
                self.motion.cancel(now)
        self.motion.followed = None
        self.motion.min_person_distance = PERSON_MIN_DISTANCE
        if self.navigation is not None:
            self.navigation.ignore_people = frozenset()

    def _fail(self, code: str, detail: str, now: float) -> None:
        self._release(now, stop=True)
        reason = f"{code}: {detail}"
        self.state = replace(self.state, phase=GAVE_UP, reason=reason)
        self.set_status(failed(reason), now)
        self._publish(now)

    def _reset(self) -> None:
        self._belief = None
        self._others = set()
        self._shadowed = {}
        self._strangers = {}
        self._stranger_seen = {}
        self._lost_since = None
        self._last_call = -math.inf
        self._goal = None
        self._goal_t = -math.inf
        self._search_turns = 0
        self._search_heading = None
        self._trail = []
        self._search_goal = None
        self._plan, self._plan_index, self._searched = None, 0, []
        self._looking_since = None
        self._recent = []
        self._waiting_since = None
        self._asked_at = None
        self._end_contest()
        self._unsettled = False
        self._first_seen = {}
        self._usual_pace = USUAL_PACE
        self._look, self._looks, self._look_t = None, 0, None
        self._views, self._views_of = [], None
        self._matched, self._matched_t = None, -math.inf
        self.ambiguous = False
        self._said_unsure = False
        self._pace_watch = PaceWatch()

    def _publish(self, now: float) -> None:
        self.write("following/state", self.state, now)


_RANGES = {"distance": (0.5, 5.0), "min_distance": (0.4, 5.0), "give_up_after": (1.0, 600.0),
           "search_after": (0.0, 600.0), "call_every": (1.0, 600.0)}


def _checked(params: FollowParams) -> FollowParams:
    for name, (low, high) in _RANGES.items():
        value = getattr(params, name)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and low <= value <= high):
            raise ValueError(f"following {name} = {value!r} is outside {low} .. {high}")
    if params.min_distance > params.distance:
        raise ValueError(f"following min_distance = {params.min_distance} m is more than "
                         f"distance = {params.distance} m; make it at most the distance")
    if not params.call.strip():
        raise ValueError("following call is empty; give the words the robot calls out with")
    if not params.excuse.strip():
        raise ValueError("following excuse is empty; give the words the robot asks people "
                         "in its way to let it pass with")
    return params
