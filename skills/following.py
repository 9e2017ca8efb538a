"""Following a customer: keep one tracked person at a distance, find them again after a loss.

`follow(target, now)` picks the customer (a track id, else the user) and from then on, each tick:

- **following**: the customer is seen; the robot drives (through the navigation skill, so
  around shelves and other shoppers) towards the customer, led by their velocity so it does not
  trail, at a pace that matches theirs plus a correction for the distance error; walking, it
  keeps half its stopping distance beyond `distance`. Never closer than `min_distance`: the
  safety arbiter refuses to drive at anybody inside it while following, and anybody (the
  customer too) walking at the robot inside it makes it back off (`skills.giving_way`).
- **waiting**: the customer stands (or comes closer) within reach: the robot faces them and
  closes in slowly to half its stopping distance inside `distance` (backing off to it, where it
  can see behind, when a search left it closer).
- **hidden**: the customer's track is not seen (another shopper, a cart, a shelf end between
  them). The robot keeps going towards where the customer's Kalman state predicts them.
- **searching**: hidden for `search_after` s: the robot drives to within `distance` of the
  predicted place, turns round there, then once more 3 m on along her trail, and calls out
  every `call_every` s.
- **gave up**: not found for `give_up_after` s: the skill fails with a reason saying where it
  last saw them and for how long it searched.

Finding the customer again is *gated*: only a confirmed track (the camera confirms tracks, so a
door post the laser takes for legs never qualifies) whose position lies within a gate around the
predicted position (growing with the time unseen at walking pace) may become the customer,
never a track that was seen as somebody else while the customer was in view, and never two
that fit equally (the robot waits rather than guesses). Once the camera has shown her a few
times, her look (a running average of the camera's colour histograms of her,
`skills.people.appearance`) decides: a track that looks like her may be taken back whatever
its id, only such a track, and her own track stops being hers when its fresh views stop looking
like her. Without appearance, a track born after the loss outside the gate of that moment
(someone who came from elsewhere) is not her either.

Typed status: running ('' following, 'waiting', 'hidden for N s', 'searching for N s'),
failed (`NO_CUSTOMER`, `GAVE_UP` as the reason's first words), idle after `cancel`.
`following/state` (a `FollowState`) carries the same as values for the percepts.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from skills import giving_way
from skills.localization import Localization
from skills.motion import Goal, Motion
from skills.perception import PeoplePerception
from skills.people import appearance
from skills.people.track import CONFIRMED
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
TRAIL_STEP = 0.3          # m between two points of the customer's trail
TRAIL_LENGTH = 40         # points kept (12 m)
FREE_MARGIN = 0.1         # m beyond the robot's radius a goal must keep from walls
PERSON_CLEARANCE = 0.15   # m: a track closer than this to a wall is not a person
BRAKE = 0.8               # share of the base's max_accel counted on for stopping
LATENCY_MARGIN = 0.1      # m covered before a stop command takes effect (a tick or two)
PACE_WINDOW = 0.4         # s over which the customer's walked distance gives their pace
FRESH = 0.15              # s: a candidate for re-acquisition must have been seen this recently
CONTEST_NEAR = 0.8        # m: another track this close to the customer's may swap ids with it
UNTANGLE_REACH = 1.2      # m from where the customer should be after a contest, at most
USUAL_PACE = 0.5          # m/s a customer walks at, until her own pace is known ...
PACE_LEARNING = 0.05      # ... from a running average of her pace while walking
CREEP = 0.2               # m/s at most, closing in on a customer who stands
SEARCH_AHEAD = 3.0        # m beyond the last seen place, along her trail, searched second
BIRTH_MARGIN = 0.3        # m a new track may be born outside the gate and still be the customer
LOOK_WEIGHT = 0.1         # share of each new camera view of the customer in her look
LOOK_KNOWN = 5            # views of her before her look is trusted
MISMATCHES = 2            # fresh views in a row unlike her, and none like her for
UNLIKE_FOR = 0.6          # this long (s): her track is on somebody else


@dataclass(frozen=True)
class FollowParams:
    distance: float = 1.2          # m, robot centre to customer centre
    min_distance: float = 0.8      # m: never drives closer than this
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
    max_gate: float = 6.0          # m: ... up to this
    jump: float = 1.5              # m: the target track this far off the prediction is a swap
    clearly_nearer: float = 0.5    # a candidate wins only at this fraction of the next distance
    call: str = CALL


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


@dataclass
class _Belief:
    """The customer's last seen Kalman state, for prediction while unseen."""
    x: float
    y: float
    vx: float
    vy: float
    t: float

    def at(self, now: float, horizon: float) -> tuple[float, float]:
        dt = min(max(now - self.t, 0.0), horizon)
        return self.x + self.vx * dt, self.y + self.vy * dt

    @property
    def speed(self) -> float:
        return math.hypot(self.vx, self.vy)


class Following(Skill):
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
        self._lost_since: float | None = None
        self._last_call = -math.inf
        self._goal: tuple[float, float] | None = None
        self._goal_t = -math.inf
        self._search_turns = 0
        self._search_heading: float | None = None
        self._trail: list[tuple[float, float]] = []   # where the customer walked, every 0.3 m
        self._search_goal: tuple[float, float] | None = None
        self._searched_ahead = False
        self._recent: list[tuple[float, float, float]] = []    # (t, x, y) seen, newest last
        self._waiting_since: float | None = None
        self._contest: _Belief | None = None          # the customer before someone came close
        self._contest_ids: set[int] = set()
        self._first_seen: dict[int, tuple[float, float, float]] = {}   # id: (t, x, y)
        self._usual_pace = USUAL_PACE
        self._look: np.ndarray | None = None           # what the customer looks like ...
        self._looks = 0                                # ... from this many camera views
        self._look_t: float | None = None              # time of the newest view used
        self._mismatches = 0
        self._matched: _Belief | None = None           # her state at the last view like her
        self._matched_t = -math.inf                    # ... and its time

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
        self._publish(now)

    def _give_way(self, robot, now: float) -> None:
        """Anybody (the customer too) walking at the robot inside `min_distance` makes it
        back off, facing them (`skills.giving_way`); whatever the phase wanted waits."""
        intruder = giving_way.closing_in(self.perception.tracks, robot, self.params.min_distance)
        if intruder is None:
            return
        self._hold(now)
        self.motion.start(giving_way.back_off(intruder, robot), now)

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
        self._search_heading = None
        self._search_goal = None
        self._search_turns = 0
        self._searched_ahead = False
        d = math.hypot(track.x - robot[0], track.y - robot[1])
        speed = self._pace(track, now)
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
        # walking, keep half the stopping distance beyond the setpoint: should the customer
        # stop dead, the robot comes to rest about as far inside it as it followed outside
        error = d - (p.distance + self._stopping_distance(pace) / 2)
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
        else:
            self._face(track.x, track.y, robot, now)

    def _stopping_distance(self, pace: float) -> float:
        """m the robot needs to stop from `pace` (braking at BRAKE of max_accel, plus what it
        covers before the stop takes effect)."""
        brake = BRAKE * self.motion.limits.max_accel
        return pace * pace / (2 * brake) + LATENCY_MARGIN * pace / 0.5

    # -- unseen ----------------------------------------------------------------------------

    def _on_unseen(self, robot, now: float) -> None:
        p = self.params
        if self._lost_since is None:
            self._lost_since = self._belief.t
            self.state = replace(self.state, losses=self.state.losses + 1)
        lost_for = now - self._lost_since
        seen = (self._belief.x, self._belief.y)
        predicted = self._free_towards(seen, self._belief.at(now, p.predict_for)) or seen
        self.motion.followed = None            # unseen: everybody near counts for the speed cap
        if lost_for >= p.give_up_after:
            seen = self.state.last_seen
            self.state = replace(self.state, distance=None, lost_for=lost_for, predicted=predicted)
            self._fail(GAVE_UP_REASON, f"not seen for {lost_for:.0f} s; last seen at "
                       f"({seen[0]:.1f}, {seen[1]:.1f}), searched there and called "
                       f"{self.state.calls} time(s)", now)
            return
        if lost_for < p.search_after:
            phase = HIDDEN
            self._approach_prediction(predicted, robot, now)
        else:
            phase = SEARCHING
            self._search(predicted, robot, now)
        reason = f"{phase} for {int(lost_for)} s"
        self._waiting_since = None
        self.state = replace(self.state, phase=phase, distance=None, lost_for=lost_for,
                             waiting_for=0.0, predicted=predicted, reason=reason)
        self.set_status(SkillStatus(Status.RUNNING, reason), now)

    def _approach_prediction(self, predicted, robot, now: float) -> None:
        """Keep going to where the customer should be, stopping `distance` short of it."""
        p = self.params
        dx, dy = predicted[0] - robot[0], predicted[1] - robot[1]
        d = math.hypot(dx, dy)
        if d <= p.distance + 0.1:
            self._face(predicted[0], predicted[1], robot, now)
            return
        goal = (predicted[0] - dx / d * p.distance, predicted[1] - dy / d * p.distance)
        if not self._free(*goal):
            goal = predicted
        self._drive_to(goal, self._belief.speed + p.speed_gain * (d - p.distance), now)

    def _search(self, predicted, robot, now: float) -> None:
        """Drive to within `distance` of the predicted place; there, turn round in thirds; call
        out now and then."""
        p = self.params
        if self.speech is not None and now - self._last_call >= p.call_every:
            self._last_call = now
            self.speech.say(p.call, now)
            self.state = replace(self.state, calls=self.state.calls + 1)
        goal = self._search_goal or predicted
        d = math.hypot(goal[0] - robot[0], goal[1] - robot[1])
        nav = self.navigation
        # navigation's outcome counts only for this goal, not for the approach while hidden
        # (which stops `distance` short of the prediction, out of sight round a shelf end)
        ours = self._goal is not None and math.hypot(self._goal[0] - goal[0],
                                                     self._goal[1] - goal[1]) <= p.goal_step
        # within `distance` of the place it can see it, and she may be standing right there
        arrived = nav is None or d < p.distance or (ours and nav.status.status in (
            Status.SUCCEEDED, Status.FAILED))
        if nav is not None and ours and nav.status.failed and self._trail:
            # the predicted place cannot be reached: search from the last place on the trail
            fallback = next((pt for pt in reversed(self._trail) if self._free(*pt)), None)
            if fallback is not None and fallback != self._search_goal:
                self._search_goal = fallback
                self._goal = None
                arrived = False
        goal = self._search_goal or predicted
        if not arrived:
            self._drive_to(goal, 0.4, now)
            return
        if self._search_heading is None or abs(_wrap(self._search_heading - robot[2])) < 0.15:
            if self._search_turns >= 3 and self._search_further(goal):
                return                  # looked all round here: on to where she was heading
            self._search_heading = _wrap(robot[2] + 2 * math.pi / 3)
            self._search_turns += 1
        self._hold(now)
        self.motion.start(Goal("turn_to", bearing=self._search_heading), now)

    def _search_further(self, here) -> bool:
        """After a full turn at the predicted place, search SEARCH_AHEAD further along the
        direction her trail last took (she went on round a shelf end, out of sight from the
        corner): once. True if there is such a place."""
        if self._searched_ahead or len(self._trail) < 2:
            return False
        self._searched_ahead = True
        (x0, y0), (x1, y1) = self._trail[max(0, len(self._trail) - 4)], self._trail[-1]
        step = math.hypot(x1 - x0, y1 - y0)
        if step < 0.2:
            return False
        ahead = (x1 + (x1 - x0) / step * SEARCH_AHEAD, y1 + (y1 - y0) / step * SEARCH_AHEAD)
        # where the robot fits: near that point (she walked close along a shelf), else short of it
        goal = self._nearest_free(*ahead) or self._free_towards((x1, y1), ahead)
        if goal is None or math.hypot(goal[0] - here[0], goal[1] - here[1]) < 1.0:
            return False
        self._search_goal, self._goal = goal, None
        self._search_turns, self._search_heading = 0, None
        return True

    # -- choosing the customer -------------------------------------------------------------

    def _initial_target(self, target: int | None):
        tracks = self.perception.believed
        if target is not None:
            return next((t for t in tracks if t.id == target), None)
        user = self.perception.user
        if user is not None:
            return user
        pose = self.localization.state
        if pose is None:
            return None
        near = [t for t in tracks if t.status == CONFIRMED
                and math.hypot(t.x - pose.x, t.y - pose.y) <= 2.5]
        return min(near, key=lambda t: math.hypot(t.x - pose.x, t.y - pose.y), default=None)

    def _find_target(self, now: float):
        """The customer's track this tick: the same id while it is seen and near the
        prediction, else a gated candidate (see the module's docstring), else None."""
        p = self.params
        tracks = self.perception.believed
        predicted = self._belief.at(now, p.predict_for)
        # the gate grows as far as the customer can have walked off the prediction (round a
        # shelf end, into the next aisle); somebody else inside it is kept out by `_others`
        # and by the rule that of two candidates one must be clearly nearer
        gate = self._gate(now - self._belief.t)
        tracks = [t for t in tracks if self._plausible(t)]
        same = next((t for t in tracks if t.id == self.state.target
                     and t.id not in self._others), None)
        if same is not None and same.status == CONFIRMED:      # seen within lost_after (0.35 s)
            if math.hypot(same.x - predicted[0], same.y - predicted[1]) <= max(gate, p.jump):
                same = self._untangle(same, tracks, now)
                if same is not None and self._looks_like_someone_else(same, now):
                    self._others.add(same.id)
                    self._belief = self._matched or self._belief
                    predicted = self._belief.at(now, p.predict_for)
                    gate = self._gate(now - self._belief.t)
                    same = None
                if same is not None:
                    self._note_others(tracks, same.id)
                    return same
        candidates = sorted(
            ((math.hypot(t.x - predicted[0], t.y - predicted[1]), t) for t in tracks
             if t.status == CONFIRMED and t.last_seen >= now - FRESH and self._may_be_her(t)
             and (t.id not in self._others or self._seen_as_her_since_the_loss(t))),
            key=lambda c: c[0])
        inside = [c for c in candidates if c[0] <= gate]
        if not inside:
            return None
        if len(inside) > 1 and inside[0][0] > p.clearly_nearer * inside[1][0]:
            return None                  # two fit and neither is clearly the customer: wait
        return inside[0][1]

    # -- what she looks like (the camera's colour histograms, skills.people.appearance) --------

    @property
    def _look_known(self) -> bool:
        return self._look is not None and self._looks >= LOOK_KNOWN

    def _may_be_her(self, track) -> bool:
        """Once her look is known, only a track the camera has seen looking like her; before
        (or on a robot whose detector reports no appearance), one born where she could be."""
        if not self._look_known:
            return self._born_where_she_could_be(track)
        return (track.appearance is not None
                and appearance.distance(self._look, track.appearance) <= appearance.SAME_PERSON)

    def _seen_as_her_since_the_loss(self, track) -> bool:
        """The camera saw this track looking like her after she was lost: the tracker may
        have handed her an id that was somebody else's before (an id is not a person)."""
        return (self._look_known and track.appearance_t is not None
                and track.appearance_t > self._belief.t and self._may_be_her(track))

    def _looks_like_someone_else(self, track, now: float) -> bool:
        """Learn her look from fresh camera views of her track while nobody is close to her;
        once it is known, MISMATCHES fresh views in a row unlike her mean the track has passed
        to somebody else (someone who crossed her close, hidden behind her until then)."""
        fresh = (track.appearance is not None and track.appearance_t is not None
                 and track.appearance_t >= now - FRESH and track.appearance_t != self._look_t)
        if not fresh or self._contest is not None:
            return False        # someone close to her: the camera's view may be theirs
        self._look_t = track.appearance_t
        if self._look_known and appearance.distance(self._look, track.appearance) \
                > appearance.SAME_PERSON:
            self._mismatches += 1
            # two people at one spot (at one shelf) make one track whose views alternate
            # between them: she is still there as long as some views look like her
            return self._mismatches >= MISMATCHES and now - self._matched_t >= UNLIKE_FOR
        self._mismatches = 0
        self._matched, self._matched_t = self._belief, now
        self._learn(track.appearance)
        return False

    def _learn(self, seen) -> None:
        self._look = appearance.blend(self._look, seen, max(LOOK_WEIGHT, 1.0 / (self._looks + 1)))
        self._looks += 1

    def _gate(self, unseen: float) -> float:
        p = self.params
        return min(p.gate + p.gate_growth * max(unseen, 0.0), p.max_gate)

    def _note_births(self, now: float) -> None:
        """Where each track was first seen: a track born far from where the customer could
        have been is somebody else (a shopper who came from behind the robot), whatever it
        does later."""
        ids = set()
        for t in self.perception.believed:
            ids.add(t.id)
            self._first_seen.setdefault(t.id, (now, t.x, t.y))
        for gone in set(self._first_seen) - ids:
            del self._first_seen[gone]

    def _born_where_she_could_be(self, track) -> bool:
        """A track first seen after the customer was last seen must have been born inside the
        gate of that moment (she reappears where she could have walked to)."""
        born = self._first_seen.get(track.id)
        if born is None or born[0] <= self._belief.t:
            return True
        at = self._belief.at(born[0], self.params.predict_for)
        reach = self._gate(born[0] - self._belief.t) + BIRTH_MARGIN
        return math.hypot(born[1] - at[0], born[2] - at[1]) <= reach

    def _note_others(self, tracks, target: int) -> None:
        """People seen at the same time as the customer are somebody else, for good; not those
        close to them, whose identity the tracker may just have swapped with theirs, nor one
        who looks like her (her track may be the one that passed to somebody else)."""
        self._others.update(t.id for t in tracks if t.id != target and t.status == CONFIRMED
                            and t.id not in self._contest_ids
                            and not (self._look_known and self._may_be_her(t)))

    def _untangle(self, target, tracks, now: float):
        """Two people passing within CONTEST_NEAR of each other can swap track ids. While
        someone is that close to the customer, remember where the customer was and how they
        moved before; when the two are apart again, the customer is the track nearest that
        prediction (one who stood still stayed, one who walked went on)."""
        near = {t.id for t in tracks if t.id != target.id and t.status == CONFIRMED
                and math.hypot(t.x - target.x, t.y - target.y) < CONTEST_NEAR}
        if near:
            if self._contest is None:
                b = self._belief
                standing = self._pace(target, now) < self.params.standing
                self._contest = _Belief(b.x, b.y, 0.0 if standing else b.vx,
                                        0.0 if standing else b.vy, b.t)
            self._contest_ids |= near
            return target
        if self._contest is None:
            return target
        before, ids = self._contest, self._contest_ids | {target.id}
        self._contest, self._contest_ids = None, set()
        expected = before.at(now, self.params.predict_for)
        options = [t for t in tracks if t.id in ids and t.status == CONFIRMED]
        if self._look_known:             # she looks like herself: that settles it, if seen
            options = [t for t in options if self._may_be_her(t)] or options
        best = min(options, key=lambda t: math.hypot(t.x - expected[0], t.y - expected[1]))
        if math.hypot(best.x - expected[0], best.y - expected[1]) > UNTANGLE_REACH:
            # none of them is where the customer should be: they are hidden; the track that
            # walked off with the id was somebody else
            self._others.add(target.id)
            self._belief = before
            return None
        if best.id != target.id:
            self._recent = []                  # the pace so far was somebody else's
            self._others.add(target.id)
            self.state = replace(self.state, swaps=self.state.swaps + 1)
        return best

    def _pace(self, track, now: float) -> float:
        """The customer's speed: the smaller of the track's (a constant-velocity Kalman filter
        is slow to see a stop) and the distance walked over the last PACE_WINDOW seconds."""
        kalman = math.hypot(track.vx, track.vy)
        past = next(((t, x, y) for t, x, y in self._recent if now - t <= PACE_WINDOW + 1e-6),
                    None)
        if past is None or now - past[0] < PACE_WINDOW / 2:
            return kalman
        walked = math.hypot(track.x - past[1], track.y - past[2]) / (now - past[0])
        return min(kalman, walked)

    def _see(self, track, now: float) -> None:
        self._belief = _Belief(track.x, track.y, track.vx, track.vy, now)
        self._recent.append((now, track.x, track.y))
        while self._recent and now - self._recent[0][0] > PACE_WINDOW + 1e-6:
            self._recent.pop(0)
        if not self._trail or math.hypot(track.x - self._trail[-1][0],
                                         track.y - self._trail[-1][1]) >= TRAIL_STEP:
            self._trail.append((track.x, track.y))
            del self._trail[:-TRAIL_LENGTH]

    def _plausible(self, track) -> bool:
        """A person's centre cannot lie in or against a wall or shelf: a track there has been
        pulled onto a shelf corner or door post (laser legs) and is not the customer."""
        nav = self.navigation
        return nav is None or bool(nav.grid.clearance(track.x, track.y) >= PERSON_CLEARANCE)

    def _free(self, x: float, y: float) -> bool:
        """The robot fits at (x, y) with a margin (True without a map)."""
        nav = self.navigation
        if nav is None:
            return True
        margin = nav.profile.radius + FREE_MARGIN
        return bool(nav.grid.clearance(x, y) >= margin)

    def _free_towards(self, start, end):
        """The point nearest `end` on the segment from `start` where the robot fits, walking
        back from `end` (a prediction that runs into a shelf stops before it); None if none."""
        for k in range(10, -1, -1):
            f = k / 10
            x, y = start[0] + f * (end[0] - start[0]), start[1] + f * (end[1] - start[1])
            if self._free(x, y):
                return x, y
        return None

    def _nearest_free(self, x: float, y: float):
        """The nearest point within 0.6 m of (x, y) where the robot fits (a customer walking
        close along a shelf), or None."""
        for r in (0.1, 0.2, 0.3, 0.45, 0.6):
            for k in range(12):
                a = k * math.pi / 6
                if self._free(x + r * math.cos(a), y + r * math.sin(a)):
                    return x + r * math.cos(a), y + r * math.sin(a)
        return None

    def _on_trail(self, cx: float, cy: float):
        """A point of the customer's own trail about `distance` behind them where the robot
        fits: where the straight line from the robot would cut a shelf corner."""
        back = 0.0
        prev = (cx, cy)
        for x, y in reversed(self._trail):
            back += math.hypot(prev[0] - x, prev[1] - y)
            prev = (x, y)
            if back >= self.params.distance and self._free(x, y):
                return x, y
        return None

    # -- driving ---------------------------------------------------------------------------

    def _drive_to(self, goal, speed: float, now: float) -> None:
        nav = self.navigation
        if nav is None:
            return
        top = nav.limits.max_speed
        speed = min(max(speed, 0.05), top)
        renew = (self._goal is None or nav.state.phase not in ("driving", "blocked")
                 or math.hypot(goal[0] - self._goal[0], goal[1] - self._goal[1]) > self.params.goal_step
                 or now - self._goal_t >= self.params.goal_every)
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
        self._lost_since = None
        self._last_call = -math.inf
        self._goal = None
        self._goal_t = -math.inf
        self._search_turns = 0
        self._search_heading = None
        self._trail = []
        self._search_goal = None
        self._searched_ahead = False
        self._recent = []
        self._waiting_since = None
        self._contest = None
        self._contest_ids = set()
        self._first_seen = {}
        self._usual_pace = USUAL_PACE
        self._look, self._looks, self._look_t = None, 0, None
        self._mismatches = 0
        self._matched, self._matched_t = None, -math.inf

    def _publish(self, now: float) -> None:
        self.write("following/state", self.state, now)


def _approaching(track, robot) -> bool:
    dx, dy = robot[0] - track.x, robot[1] - track.y
    d = math.hypot(dx, dy)
    return d > 0.0 and (track.vx * dx + track.vy * dy) / d > 0.2


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


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
    return params
