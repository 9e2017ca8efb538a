"""Searching: what the robot does while the customer is unseen.

- **hidden**: the robot keeps going towards where her Kalman state predicts her, stopping
  `distance` short of it (a customer faster than the robot is kept up with as far as it can).
- **searching**: hidden for `search_after` s: the robot works through a *search plan* made
  once, at the moment the search begins (`search_plan`), and calls out every `call_every` s:

  1. the predicted place (her last seen state run on for `predict_for` s), looking along her
     heading (round in thirds when she stood);
  2. then the places where she is likely to reappear, expanding outwards from where she
     vanished: SEARCH_AHEAD on along the direction her trail last took (the way she can
     walk on nearest it: turning into an aisle, up the aisle), and the map's aisle
     ends and crossings (its places named `aisle…`; in the store, where each aisle meets the
     front or back aisle) within SEARCH_REACH of walking (round shelves,
     `room.walking_distances`), nearest first, those along her heading counted nearer than
     those aside or behind (a place straight behind her counts
     twice its walking distance). At an aisle end the robot looks into the aisle (the
     place's heading; the people detector's 240° take in the cross aisle on both sides too)
     for LOOK_DWELL s;
  3. when all are seen, the aisle ends it left out and the map's places where shoppers stand
     (named `shelf…`), the nearest where she vanished first, visited as a walk from where the
     robot is (`further_lookouts`); once every place is planned and seen, it goes back to the
     plan's second place (the likeliest after the predicted one, where she had been heading)
     and goes round again, until she comes back into view or the application's
     `give_up_after` runs out (the phase machine's; the reason names the places searched).

  A place on her way (the predicted place, the place on along her way) looked at without her
  leads on along her way (`_walk_on`): as far as she can have walked since she vanished, or,
  where her way passes the mouth of an aisle she may have turned into, into that aisle first
  and on from abreast of it, one aisle at a time, as a person looking for somebody glances
  down each aisle they pass.

  The further places are visited as a walk (`_tour`): each next the one whose walk from the
  last plus its walk from where she vanished is least, so the robot does not go to and fro
  across the store.

  A place need not be reached to be looked at (with a map): one that has been within SEE_FROM,
  within IN_VIEW of the robot's heading, with the map's line to it (for an aisle end, to a
  point INTO m into the aisle) clear and no tracked person within HIDDEN_BY of that line (one
  standing at the place itself does not hide it), for LOOK_DWELL s in all, is looked at, on
  the way to another place too; the search passes it. A place the robot has got no
  WAY_PROGRESS nearer for SEARCH_BLOCKED s (its way blocked by a crowd or by somebody
  standing in an aisle, the robot backing off from them) is passed over for now (not counted
  as looked at: the round after the last place comes back to it). Reaching each aisle end in
  turn took one or two places in 30 s (issue 23).

A part of `Following` (`skills.following.follower`); it reads `params`, `navigation`,
`speech`, the belief and her trail (`skills.following.identity`) and where the robot fits
(`skills.following.room`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from skills.motion import Goal
from skills.status import Status

SEARCH_AHEAD = 3.0        # m beyond the last seen place, along her trail
SEARCH_REACH = 14.0       # m of walking from where she vanished: aisle ends further are left out
MAX_LOOKOUTS = 7          # places in a plan at most (the predicted place included)
BEHIND_WEIGHT = 1.0       # a place straight behind her counts (1 + this) times its distance
COURSE_WEIGHT = 0.2       # ... and behind her course (her trail as a whole), 1.2 times
MERGE = 1.5               # m: a place this near one already planned is seen from there
LOOK_DWELL = 1.5          # s looking along each bearing
ARRIVE = 0.5              # m from an aisle end counts as there
LOOKOUT_PREFIX = "aisle"  # the map's places that are aisle ends and crossings
STOP_PREFIX = "shelf"     # the map's places where shoppers stand (searched once ends are seen)
INTO = 2.0                # m into the aisle the robot must see for an aisle end to count
HEADING_BASE = 1.5        # m of her trail her heading is taken over
TRAIL_GAP = 1.0           # m between two points of her trail (identity.TRAIL_STEP apart as
                          # she is seen): she was lost in between; her heading is not taken
                          # across it
ALIGNED = 0.15            # rad: a turn this close to its bearing is done
SEE_FROM = 3.0            # m: a place of the plan this near, in view and not hidden, is looked at
IN_VIEW = math.radians(100)   # rad either side of the robot's heading a place counts in view
                              # (the people detector sees 240 deg)
HIDDEN_BY = 0.35          # m: a tracked person this near the line of sight hides what is behind
AT_PLACE = 0.6            # m: ... unless standing this near the place itself
SEARCH_BLOCKED = 5.0      # s without getting WAY_PROGRESS nearer a place before the search
WAY_PROGRESS = 0.3        # m   goes on (a blocked way, backing off from someone, a crowd)
PREDICTED = "where she should be"
AHEAD = f"{SEARCH_AHEAD:.0f} m on along her way"
FURTHER = "further along her way"
WALK_ON_SPREAD = math.radians(30)   # directions tried either side of her heading (a trail's
WALK_ON_STEP = math.radians(5)      # heading runs some degrees off the aisle she walked up)
WALK_ON_MAX = 10.0        # m at most beyond the place looked at
TURNING_OFF = 3.5         # m at most from her way to the mouth of an aisle she may have turned
                          # into (the store's cross aisles are 3.5 m wide)
TURNING_ACROSS = 0.5      # |cos| at most between her way and that aisle (60 to 120 degrees)
AHEAD_SPREAD = math.radians(60)   # directions tried either side of her heading for the place
                                  # SEARCH_AHEAD on (turning into an aisle, her heading lags)


@dataclass(frozen=True)
class Lookout:
    """A place of the search plan: where to stand, where to look on arrival (None: round in
    thirds), why it is in the plan, the point the robot must see for the place to count as
    looked at (None: the place itself; an aisle end: INTO m into the aisle), and for an aisle
    she may have turned into from her way, the point of her way abreast of it and her way's
    direction ((x, y, rad): the walk on goes on from there; None: from the place, along its
    first bearing)."""
    x: float
    y: float
    bearings: tuple[float, ...] | None
    why: str
    into: tuple[float, float] | None = None
    way: tuple[float, float, float] | None = None


def search_plan(predicted, seen, heading, ends, walk=None, ahead=None,
                course=None) -> list[Lookout]:
    """The places to search, in order, for a customer last seen at `seen` walking along
    `heading` (a unit vector, or None when she stood), predicted at `predicted`.

    `ends` are the map's aisle ends and crossings as (name, x, y, heading rad: into the
    aisle); `walk(x, y)` is the walking distance from `seen` (None: cannot be walked to;
    default: the straight line); `ahead` is the point SEARCH_AHEAD on along her trail where
    the robot fits (None: no such point); `course` the direction of her trail as a whole (a
    unit vector or None), which breaks ties between places as far off her heading. See the
    module's docstring for the order. (Visiting the plan's places as a walk, each next the
    least walk plus cost, was tried and not kept: on HOROS crowd10 seed 2 it turned the robot
    back to aisle A5's south end 5.2 m short of her, who stood on up aisle A4.)"""
    walk = walk or (lambda x, y: math.hypot(x - seen[0], y - seen[1]))
    plan = [Lookout(predicted[0], predicted[1], _along(heading), PREDICTED)]
    candidates = []
    if ahead is not None:
        along = (ahead[2],) if len(ahead) > 2 else _along(heading)
        candidates.append((_cost(ahead[:2], seen, heading, walk, course), Lookout(
            ahead[0], ahead[1], along, AHEAD)))
    for name, x, y, th in ends:
        cost = _cost((x, y), seen, heading, walk, course)
        if cost is not None:
            candidates.append((cost, _end(name, x, y, th)))
    return _fill(plan, candidates, MAX_LOOKOUTS)


def _end(name, x, y, th) -> Lookout:
    """An aisle end: looked at once the robot sees INTO m into the aisle (from beside its
    mouth in the cross aisle the mouth itself is in view, the aisle is not: fast seed 2 passed
    aisle A1's north end from 2 m off while she stood 2.5 m inside it, issue 23)."""
    return Lookout(x, y, (th,), name, (x + INTO * math.cos(th), y + INTO * math.sin(th)))


def further_lookouts(plan, seen, ends, walk=None, stops=(), start=None,
                     walk_from=None) -> list[Lookout]:
    """The next places once the whole plan is seen: the aisle ends and crossings it left
    out (too far, or beyond MAX_LOOKOUTS) and the `stops` (the map's places where shoppers
    stand, as (name, x, y, heading)), the MAX_LOOKOUTS - 1 nearest `seen` (walking distance,
    any reach: expanding outwards); none when every one has been planned. A customer faster
    than the robot is searched for across the store where she may stand, not waited for where
    she was last. Given the robot's position `start`, they are visited as a walk from there
    (`_tour`: each next the least walk from the last plus its walk from `seen`;
    `walk_from(point)` gives walking distances from a point): nearest `seen` first sent the
    robot to and fro across the store (fast seed 2)."""
    walk = walk or (lambda x, y: math.hypot(x - seen[0], y - seen[1]))
    candidates = []
    for name, x, y, th in ends:
        d = walk(x, y)
        if d is not None:
            candidates.append((d, _end(name, x, y, th)))
    for name, x, y, th in stops:
        d = walk(x, y)
        if d is not None:
            candidates.append((d, Lookout(x, y, (th,), name)))
    more = _fill(list(plan), candidates, len(plan) + MAX_LOOKOUTS - 1)[len(plan):]
    if start is None:
        return more
    return _tour(more, start, walk_from, {lookout: d for d, lookout in candidates})


def _tour(places, start, walk_from=None, cost=None) -> list[Lookout]:
    """`places` in the order of a walk from `start`: each next the one whose walk from the
    last plus its `cost` (a dict: lookout -> its cost from where she vanished; none: 0) is
    least, so that the walk stays near where she is likely to be while it saves going to
    and fro."""
    left, order, here = list(places), [], start
    cost = cost or {}
    while left:
        walk = walk_from(here) if walk_from is not None else None
        walk = walk or (lambda x, y, h=here: math.hypot(x - h[0], y - h[1]))
        far = [walk(q.x, q.y) for q in left]
        k = min(range(len(left)), key=lambda i: math.inf if far[i] is None
                else far[i] + cost.get(left[i], 0.0))
        here = (left[k].x, left[k].y)
        order.append(left.pop(k))
    return order


def _fill(plan, candidates, size) -> list[Lookout]:
    """`plan` with the cheapest candidates appended up to `size` places, leaving out any
    seen from one already planned (`_seen_from`)."""
    for _, lookout in sorted((c for c in candidates if c[0] is not None), key=lambda c: c[0]):
        if len(plan) >= size:
            break
        if not any(_seen_from(lookout, q) for q in plan):
            plan.append(lookout)
    return plan


def _seen_from(lookout: Lookout, planned: Lookout) -> bool:
    """`lookout` is seen from a place already planned: within MERGE of it, and for an aisle
    end, that place inside the aisle beyond its mouth or itself looking into the same aisle
    (their INTO points within MERGE). Beside the mouth, in the cross aisle, a shelf's corner
    hides the aisle: the aisle A5 end 1.2 m from where she should have been was left out as
    seen from there; the robot looked at that place from the back aisle while she walked
    down A5, and searched the aisles behind (crowd10 seed 0, issue 23)."""
    if math.hypot(lookout.x - planned.x, lookout.y - planned.y) >= MERGE:
        return False
    if lookout.into is None:
        return True
    if planned.into is not None:
        return math.hypot(lookout.into[0] - planned.into[0],
                          lookout.into[1] - planned.into[1]) < MERGE
    into_x, into_y = lookout.into[0] - lookout.x, lookout.into[1] - lookout.y
    return (planned.x - lookout.x) * into_x + (planned.y - lookout.y) * into_y >= 0.0


def _along(heading):
    """Along her heading (the people detector sees 240°: ahead and both sides); None (round
    in thirds) when she stood."""
    if heading is None:
        return None
    return (math.atan2(heading[1], heading[0]),)


def _cost(point, seen, heading, walk, course=None) -> float | None:
    """Walking distance to `point`, counted longer the further it lies off her heading (and,
    by a little, off her course)."""
    d = walk(point[0], point[1])
    if d is None or d > SEARCH_REACH:
        return None
    return d * _off(point, seen, heading, BEHIND_WEIGHT) * _off(point, seen, course,
                                                                 COURSE_WEIGHT)


def _off(point, seen, direction, weight: float) -> float:
    """1 for a point straight along `direction` from `seen`, 1 + weight straight behind."""
    if direction is None:
        return 1.0
    dx, dy = point[0] - seen[0], point[1] - seen[1]
    r = math.hypot(dx, dy)
    cos = 1.0 if r < 1e-6 else (dx * direction[0] + dy * direction[1]) / r
    return 1.0 + weight * (1.0 - cos) / 2.0


class Searching:
    """Approaching the prediction, then working through the search plan (a part of
    `Following`)."""

    def _where_she_should_be(self, now: float) -> tuple[float, float]:
        """Her last seen state run on for up to `predict_for` s; walking, along the direction
        her trail last took at no less than her usual pace (a track lost at the edge of the
        detector's range has slowed and veered before it was dropped: a fast walker is
        further on than its velocity says)."""
        b, p = self._belief, self.params
        heading = self._heading()
        if b.speed < p.standing or heading is None:
            return b.at(now, p.predict_for)
        pace = max(b.speed, self._usual_pace)
        dt = min(max(now - b.t, 0.0), p.predict_for)
        return b.x + heading[0] * pace * dt, b.y + heading[1] * pace * dt

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
        """Work through the search plan (made at the first call of a loss); call out now and
        then."""
        p = self.params
        if self.speech is not None and now - self._last_call >= p.call_every:
            self._last_call = now
            self.speech.say(p.call, now)
            self.state = replace(self.state, calls=self.state.calls + 1)
        if self._plan is None:
            self._plan = self._make_plan(predicted)
            self._plan_index, self._searched = 0, []
            self._search_goal = None
            self._viewed, self._view_t, self._way = {}, None, None
        self._watch(robot, now)
        lookout = self._plan[min(self._plan_index, len(self._plan) - 1)]
        if self._plan_index == 0 and self._search_goal is None:
            self._search_goal = (lookout.x, lookout.y)
        goal = self._search_goal or (lookout.x, lookout.y)
        if self._looked_at(self._plan_index):
            self._done_with(lookout)
            return
        if not self._arrived(goal, lookout, robot, now):
            if self._no_way(goal, robot, now):
                self._done_with(lookout, looked=False)
                return
            self._drive_to(goal, self.navigation.limits.max_speed if self.navigation else 0.4,
                           now)
            return
        if self._look_round(lookout, robot, now):
            return
        if lookout.why not in self._searched:
            self._searched.append(lookout.why)
        self._viewed[self._plan_index] = LOOK_DWELL
        self._done_with(lookout)

    def _done_with(self, lookout, looked: bool = True) -> None:
        """On from the current place (looked at, or its way blocked): the plan expands when
        its last place is done. A place on her way looked at without her leads on along it
        first (`_walk_on`)."""
        if looked and lookout.why in (PREDICTED, AHEAD, FURTHER):
            self._walk_on(lookout)
        if self._plan_index + 1 >= len(self._plan):
            seen = (self._belief.x, self._belief.y)
            pose = self.localization.state
            start = None if pose is None else (pose.x, pose.y)
            self._plan.extend(further_lookouts(self._plan, seen, self._lookouts(),
                                               self._walking_from(seen),
                                               self._lookouts(STOP_PREFIX), start,
                                               self._walking_from))
        self._next_lookout()

    def _walk_on(self, lookout) -> None:
        """She walked on: the next place is further along her way from `lookout`, as far as
        she can have walked since she vanished (her usual pace) and a straight line the
        robot fits on runs, along the direction within WALK_ON_SPREAD of her heading that runs
        furthest (up an aisle she walked into: the detector sees 5 m of a 10 m aisle, and the
        robot looked from its mouth while she walked on beyond, crowd20 seeds 0 and 2), or,
        when her way passes the mouth of an aisle she may have turned into, that aisle first
        (`_first_turning`). No place is added when she stood, or when it would not lie MERGE
        beyond this one."""
        heading = self._heading()
        if self.navigation is None or heading is None or self._lost_since is None \
                or self._belief.speed < self.params.standing:
            return
        seen = (self._belief.x, self._belief.y)
        now = self._view_t if self._view_t is not None else self._lost_since
        start = lookout.way[:2] if lookout.way else (lookout.x, lookout.y)
        reach = self._usual_pace * max(now - self._lost_since, 0.0) \
            - math.hypot(start[0] - seen[0], start[1] - seen[1])
        reach = min(reach, WALK_ON_MAX)
        if reach < MERGE:
            return
        # on along the way looked along there (the place on her way: the direction she can
        # walk on, `_walkable_ahead`), else her heading
        if lookout.way:
            base = lookout.way[2]
        else:
            base = (lookout.bearings[0] if lookout.bearings
                    else math.atan2(heading[1], heading[0]))
        best = self._longest_run(start, base, WALK_ON_SPREAD, reach)
        if best is None:
            return
        (x, y), th = best
        at = self._plan_index + 1
        further = self._first_turning(start, (x, y), th) or Lookout(x, y, (th,), FURTHER)
        self._plan.insert(at, further)
        self._viewed = {k if k < at else k + 1: v for k, v in self._viewed.items()}

    def _first_turning(self, start, end, th: float):
        """The first aisle her way from `start` to `end` (along `th`) passes the mouth of, as
        a place on her way (looked into from its mouth, the walk on going on from abreast of
        it); None when it passes none not yet looked at. Walked on 10 m along the back aisle,
        the robot passed the end of aisle A5, 3 m aside, where she had turned in, and came
        back to it only after the next 10 m (fast seed 11, issue 23)."""
        length = math.hypot(end[0] - start[0], end[1] - start[1])
        ux, uy = math.cos(th), math.sin(th)
        looked = [q.into for k, q in enumerate(self._plan) if q.into and self._looked_at(k)]
        turnings = []
        for name, x, y, aisle in self._lookouts():
            along = (x - start[0]) * ux + (y - start[1]) * uy
            abreast = (start[0] + along * ux, start[1] + along * uy)
            mouth = _end(name, x, y, aisle)
            if ARRIVE < along <= length and self._turns_off(abreast, th, mouth, looked):
                turnings.append((along, replace(mouth, why=FURTHER,
                                                way=(abreast[0], abreast[1], th))))
        return min(turnings, key=lambda t: t[0])[1] if turnings else None

    def _turns_off(self, abreast, th: float, mouth: Lookout, looked) -> bool:
        """The aisle whose end is `mouth` (`_end`: looking into it, up to its `into` point)
        turns off her way at `abreast` (along `th`): within TURNING_OFF aside, across her way
        (TURNING_ACROSS), opening away from it, not looked into yet (an `into` of `looked`
        within MERGE) and seen into from her way (a dead end closed towards her is not)."""
        dx, dy = mouth.x - abreast[0], mouth.y - abreast[1]
        aisle, into = mouth.bearings[0], mouth.into
        return (math.hypot(dx, dy) <= TURNING_OFF
                and abs(math.cos(aisle - th)) <= TURNING_ACROSS
                and dx * math.cos(aisle) + dy * math.sin(aisle) >= 0.0
                and all(math.hypot(into[0] - a, into[1] - b) >= MERGE for a, b in looked)
                and self._clear_line(abreast, into))

    def _clear_run(self, start, th: float, reach: float):
        """(metres, (x, y)): how far from `start` along `th`, up to `reach`, the robot fits
        and the map's line stays clear, in 0.25 m steps; None when not a step."""
        last = None
        for k in range(1, int(reach / 0.25) + 1):
            x, y = start[0] + k * 0.25 * math.cos(th), start[1] + k * 0.25 * math.sin(th)
            if not self._free(x, y) or not self._clear_line(start, (x, y)):
                break
            last = (k * 0.25, (x, y))
        return last

    def _watch(self, robot, now: float) -> None:
        """Count the time each place of the plan is in view (with a map only: see the
        module's docstring)."""
        dt = 0.0 if self._view_t is None else min(max(now - self._view_t, 0.0), 0.5)
        self._view_t = now
        if self.navigation is None or dt <= 0.0:
            return
        people = [(t.x, t.y) for t in getattr(self.perception, "believed", ())]
        for k, lookout in enumerate(self._plan):
            if self._looked_at(k) or not self._in_view(lookout, robot, people):
                continue
            self._viewed[k] = self._viewed.get(k, 0.0) + dt
            if self._looked_at(k) and lookout.why not in self._searched:
                self._searched.append(lookout.why)

    def _looked_at(self, index: int) -> bool:
        return self._viewed.get(index, 0.0) >= LOOK_DWELL

    def _in_view(self, lookout, robot, people) -> bool:
        """Near, within the detector's field, the map's line to it (to its `into` point
        where it has one) clear and nobody on it."""
        if math.hypot(lookout.x - robot[0], lookout.y - robot[1]) > SEE_FROM:
            return False
        target = lookout.into or (lookout.x, lookout.y)
        dx, dy = target[0] - robot[0], target[1] - robot[1]
        d = math.hypot(dx, dy)
        if d > 0.3 and abs(_wrap(math.atan2(dy, dx) - robot[2])) > IN_VIEW:
            return False
        if not self._clear_line(robot, target):
            return False
        # somebody standing at the place itself is seen there, not hiding it (a shopper at a
        # shelf held the search 9 s, fast seed 0)
        return all(_off_segment(px, py, robot, target) > HIDDEN_BY
                   or math.hypot(px - target[0], py - target[1]) < AT_PLACE
                   for px, py in people)

    def _no_way(self, goal, robot, now: float) -> bool:
        """The robot has got no WAY_PROGRESS nearer this search goal for SEARCH_BLOCKED s.
        Navigation's own "blocked" clock restarts whenever the robot backs off from someone
        and drives on, so a shopper standing in an aisle held the search for 25 s (base seed 2,
        issue 23); the distance to the goal does not restart."""
        d = math.hypot(goal[0] - robot[0], goal[1] - robot[1])
        way = self._way
        if way is None or way[0] != goal or d < way[1] - WAY_PROGRESS:
            self._way = (goal, d, now)
            return False
        return now - way[2] >= SEARCH_BLOCKED

    def _arrived(self, goal, lookout, robot, now: float) -> bool:
        """Within reach of the place (the predicted place: within `distance`, from where it
        can see it; an aisle end: ARRIVE), or navigation finished with it. The predicted
        place out of reach: the last free place of her trail instead."""
        p = self.params
        d = math.hypot(goal[0] - robot[0], goal[1] - robot[1])
        nav = self.navigation
        # navigation's outcome counts only for this goal, not for the approach while hidden
        # (which stops `distance` short of the prediction, out of sight round a shelf end)
        ours = self._goal is not None and math.hypot(self._goal[0] - goal[0],
                                                     self._goal[1] - goal[1]) <= p.goal_step
        near = p.distance if self._plan_index == 0 else ARRIVE
        arrived = nav is None or d < near or (ours and nav.status.status in (
            Status.SUCCEEDED, Status.FAILED))
        if self._plan_index == 0 and nav is not None and ours and nav.status.failed \
                and self._trail:
            fallback = next((pt for pt in reversed(self._trail) if self._free(*pt)), None)
            if fallback is not None and fallback != self._search_goal:
                self._search_goal = fallback
                self._goal = None
                return False
        return arrived

    def _look_round(self, lookout, robot, now: float) -> bool:
        """Look round at the place: in thirds where no bearings are given, else along each
        bearing for LOOK_DWELL s. True while still looking."""
        if self._search_heading is not None and abs(_wrap(self._search_heading - robot[2])) \
                >= ALIGNED:
            self._turn(now)
            return True
        if lookout.bearings is None:
            if self._search_turns >= 3:
                return False
            self._search_heading = _wrap(robot[2] + 2 * math.pi / 3)
            self._search_turns += 1
            self._turn(now)
            return True
        if self._search_heading is not None and self._looking_since is None:
            self._looking_since = now
        if self._looking_since is not None and now - self._looking_since < LOOK_DWELL:
            self._hold(now)
            return True
        if self._search_turns >= len(lookout.bearings):
            return False
        self._search_heading = lookout.bearings[self._search_turns]
        self._search_turns += 1
        self._looking_since = None
        self._turn(now)
        return True

    def _turn(self, now: float) -> None:
        self._hold(now)
        self.motion.start(Goal("turn_to", bearing=self._search_heading), now)

    def _next_lookout(self) -> None:
        """On to the next place of the plan; after the last, back to the likeliest place after
        the predicted one, to wait there (looking along it, over and over)."""
        self._search_turns, self._search_heading, self._looking_since = 0, None, None
        self._goal = None
        following = [k for k in range(self._plan_index + 1, len(self._plan))
                     if not self._looked_at(k)]
        if following:
            self._plan_index = following[0]
        else:                         # a new round: every place may be looked at again
            self._plan_index = min(1, len(self._plan) - 1)
            self._viewed = {}
        lookout = self._plan[self._plan_index]
        self._search_goal = (lookout.x, lookout.y)

    def _make_plan(self, predicted) -> list[Lookout]:
        seen = (self._belief.x, self._belief.y)
        heading = self._heading()
        ahead = None
        if heading is not None:
            x1, y1 = self._trail[-1] if self._trail else seen
            ahead = self._walkable_ahead((x1, y1), heading)
            if ahead is None:
                point = (x1 + heading[0] * SEARCH_AHEAD, y1 + heading[1] * SEARCH_AHEAD)
                # where the robot fits: near that point (she walked close along a shelf),
                # else short of it
                ahead = self._nearest_free(*point) or self._free_towards((x1, y1), point)
        return search_plan(predicted, seen, heading, self._lookouts(), self._walking_from(seen),
                           ahead, self._course())

    def _walkable_ahead(self, start, heading):
        """(x, y, direction): SEARCH_AHEAD on from `start` the way she can walk on, the
        direction within AHEAD_SPREAD of her heading whose straight run (the robot fitting,
        the map's line clear) goes furthest, the nearest her heading among equals; None
        without a map or when no direction runs MERGE. Her heading as she turns into an aisle
        points at the shelf beside it, and the point 3 m along it lay in the next aisle:
        crowd10 seed 2 searched aisle A5 while she walked up A4 (issue 23, crowdfix1)."""
        if self.navigation is None:
            return None
        best = self._longest_run(start, math.atan2(heading[1], heading[0]), AHEAD_SPREAD,
                                 SEARCH_AHEAD)
        if best is None:
            return None
        (x, y), th = best
        return x, y, _wrap(th)

    def _longest_run(self, start, base: float, spread: float, reach: float):
        """((x, y), direction): the end of the longest straight run (`_clear_run`) from
        `start` among the directions within `spread` of `base`, WALK_ON_STEP apart, the
        nearest `base` among equals; None when none runs MERGE."""
        best = None
        for k in range(int(round(spread / WALK_ON_STEP)) + 1):
            for sign in ((1,) if k == 0 else (1, -1)):
                th = base + sign * k * WALK_ON_STEP
                end = self._clear_run(start, th, reach)
                if end is not None and (best is None or end[0] > best[0] + 1e-9):
                    best = (end[0], end[1], th)
        if best is None or best[0] < MERGE:
            return None
        return best[1], best[2]

    def _course(self):
        """The direction of her trail as a whole (its first point kept to its last; a unit
        vector), None when it is shorter than HEADING_BASE."""
        if len(self._trail) < 2:
            return None
        (x0, y0), (x1, y1) = self._trail[0], self._trail[-1]
        step = math.hypot(x1 - x0, y1 - y0)
        return ((x1 - x0) / step, (y1 - y0) / step) if step >= HEADING_BASE else None

    def _heading(self):
        """The direction her trail last took (a unit vector), else her velocity's; None when
        she stood. Not across a loss: lost in an aisle, found again 5 m on at its end and lost
        again 1.3 m along the back aisle, her heading reached back to where she had first been
        lost and pointed up the aisle; the search looked north of the back aisle and in the
        aisle the robot had just come up while she walked into the next (crowd10 seed 0)."""
        trail = _since_last_gap(self._trail)
        if len(trail) >= 2:
            x1, y1 = trail[-1]
            # over HEADING_BASE of trail at least: a track fading out at the edge of the
            # detector's range drifts over its last few points
            x0, y0 = next(((x, y) for x, y in reversed(trail)
                           if math.hypot(x1 - x, y1 - y) >= HEADING_BASE), trail[0])
            step = math.hypot(x1 - x0, y1 - y0)
            if step >= 0.2:
                return (x1 - x0) / step, (y1 - y0) / step
        b = self._belief
        if b.speed >= self.params.standing:
            return b.vx / b.speed, b.vy / b.speed
        return None

    def _lookouts(self, prefix: str = LOOKOUT_PREFIX) -> list[tuple[str, float, float, float]]:
        """The map's places named `prefix`… (aisle ends and crossings by default). An aisle
        end whose heading points at a wall from inside (a dead end's closed end) is looked
        at the other way, up the aisle."""
        nav = self.navigation
        if nav is None:
            return []
        places = []
        for name, (x, y, th) in sorted(nav.grid.places.items()):
            if not name.startswith(prefix):
                continue
            if prefix == LOOKOUT_PREFIX and not self._clear_line(
                    (x, y), (x + INTO * math.cos(th), y + INTO * math.sin(th))):
                th = _wrap(th + math.pi)
            places.append((name, x, y, th))
        return places

    def _clear_line(self, a, b) -> bool:
        """The map's straight line from a to b is clear of walls and shelves: sampled every
        0.1 m or less (its ends left out), each sample clear, and each two neighbours' clear
        discs overlapping by a grid cell (the map's clearance is a cell's, up to a cell more
        than the point's), which covers the line between them. Sampled alone, a line passed
        between the grid cells of a wall one cell thick: the display closing aisle A6 did not
        hide the aisle from the back aisle, nor a shelf unit aisle A4 from A5's mouth."""
        d = math.hypot(b[0] - a[0], b[1] - a[1])
        steps = max(int(math.ceil(d / 0.1)), 1)
        if steps < 2:
            return True
        k = np.arange(1, steps) / steps
        grid = self.navigation.grid
        clear = grid.clearance(a[0] + (b[0] - a[0]) * k, a[1] + (b[1] - a[1]) * k)
        return bool((clear > 0.0).all()
                    and (clear[:-1] + clear[1:] >= d / steps + grid.resolution).all())

    @property
    def searched(self) -> list[str]:
        """The places of the current plan looked at so far."""
        return list(self._searched)


def _since_last_gap(trail: list) -> list:
    """The points of her trail since its last gap (two points more than TRAIL_GAP apart)."""
    for k in range(len(trail) - 1, 0, -1):
        if math.hypot(trail[k][0] - trail[k - 1][0], trail[k][1] - trail[k - 1][1]) > TRAIL_GAP:
            return trail[k:]
    return trail


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def _off_segment(px: float, py: float, a, b) -> float:
    """Distance from (px, py) to the segment a-b."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    f = 0.0 if length2 == 0.0 else min(max(((px - a[0]) * dx + (py - a[1]) * dy) / length2,
                                           0.0), 1.0)
    return math.hypot(px - a[0] - f * dx, py - a[1] - f * dy)
