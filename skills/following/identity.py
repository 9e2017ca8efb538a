"""Who the customer is: the follower's belief about which track is her.

The customer's last seen Kalman state (`_Belief`) predicts where she is while unseen. Finding
her again is *gated*: only a confirmed track (the camera confirms tracks, so a door post the
laser takes for legs never qualifies) whose position lies within a gate around the predicted
position (growing with the time unseen at walking pace) may become the customer, never a track
that was seen as somebody else while the customer was in view, and never two that fit equally
(the robot waits rather than guesses). Once the camera has shown her a few times, her look (a
running average of the camera's colour histograms of her, `skills.people.appearance`) decides:
a track that looks like her may be taken back whatever its id, only such a track, and a
look-alike seen apart from her while her own track looked like her is a stranger for good,
and so is a track born where a stranger's track has just vanished, when the stranger explains
where it was born clearly better than she does (`_born_as_a_stranger`: the tracker handing the
stranger a new id does not make her someone who may be taken for her).
While she is followed, the same identity score (`skills.following.score`) and its one
threshold decide each tick whether her track is still her (`_followed_score`). Without
appearance, a track born after the loss outside the gate of that moment (someone who came from
elsewhere) is not her either. Two people passing close may swap track ids: `_untangle` puts
her back on the track that best explains where she should be, together with where the others
who came close should be (`_settle`); while they are still close, the camera settles it only
when its views of both tracks agree for several views in a row (`_camera_settles`). While
legs alone keep her id, a fresh camera view of her on another track is weighed against it
(`_her_view_elsewhere`). Her track, unseen by the camera for a second, right beside a track
the camera sees as somebody else is that person's shadow (the laser split one person into two
tracks), not she (`_shadows_another`).

A part of `Following` (`skills.following.follower`); it reads `params`, `perception`,
`navigation`, `state` and keeps the belief, her look, her trail and pace, and the ids known to
be somebody else.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace


from skills.following import score
from skills.people import appearance
from skills.people.track import CONFIRMED

TRAIL_STEP = 0.3          # m between two points of the customer's trail
TRAIL_LENGTH = 40         # points kept (12 m)
PERSON_CLEARANCE = 0.15   # m: a track closer than this to a wall is not a person ...
FOLLOWED_CLEARANCE = 0.05  # m: ... unless it is her followed track (see _plausible)
PACE_WINDOW = 0.4         # s over which the customer's walked distance gives their pace
FRESH = 0.15              # s: a candidate for re-acquisition must have been seen this recently
CONTEST_NEAR = 0.8        # m: another track this close to the customer's may swap ids with it
UNTANGLE_REACH = 1.2      # m from where the customer should be after a contest, at most
CONTINUITY = 1.5          # log odds that her track kept its id through a close pass; set by
                          # hand: measured on simulated passes the prior is 3.8 (python
                          # benchmarks/calibrate_identity.py --passes 300), but the contest's
                          # other terms are not calibrated likelihood ratios and from 2.5 on her
                          # fresh view no longer outweighs it (tests fail; docs/shopping.md, cont1)
BIRTH_MARGIN = 0.3        # m a new track may be born outside the gate and still be the customer
LOOK_WEIGHT = 0.1         # share of each new camera view of the customer in her look
LOOK_KNOWN = 5            # views of her before her look is trusted
MISMATCHES = 2            # her track's last views, and those within
UNLIKE_FOR = 0.6          # this long (s), of which the best counts (see _followed_score)
VIEWS_KEPT = 20           # appearance scores of her track's views kept
LEGS_TRUSTED_FOR = 1.0    # s unseen after which only the camera finds her again (see
                          # _confirmed_since_the_loss)
STRANGER_MEMORY = 30.0    # s a stranger's last sighting is kept after their track is gone
CAMERA_SETTLES = 3        # views in a row, during a close pass, that swap her back (see
                          # _camera_settles)
VIEW_SPEAKS_FOR = 1.0     # s: a track's camera view older than this says nothing about who
                          # carries its id now (see _note_others, _shadows_another)
SHADOW_NEAR = 0.5         # m: her track this close to someone the camera sees as somebody else,
                          # itself unseen by the camera, is taken for their shadow (see
                          # _shadows_another)


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


def contestants(target, tracks) -> set[int]:
    """The ids of the confirmed tracks close enough to hers (`target`), within CONTEST_NEAR,
    to swap ids with it in a close pass. Also used by benchmarks/calibrate_identity.py's
    count. (A hysteresis, a pass settled with someone reopened only after they had been 1 m
    away or within 0.6 m, stopped two standing about 0.8 m apart from opening a pass tick
    after tick, but cost two crowd20 runs given up: tried and taken out, docs/shopping.md.)"""
    return {t.id for t in tracks if t.id != target.id and t.status == CONFIRMED
            and math.hypot(t.x - target.x, t.y - target.y) < CONTEST_NEAR}


class Identity:
    """Which track is the customer (a part of `Following`)."""

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
        self.ambiguous = False
        tracks = self.perception.believed
        predicted, gate = self._prediction(now)
        followed = None if self.state.lost else self.state.target
        tracks = [t for t in tracks if self._plausible(t, t.id == followed)]
        if self._unsettled:                   # two fitted alike after a close pass: decide again
            settled = self._settle(tracks, now)
            if settled is not None:
                self._note_others(tracks, settled.id, now)
                return settled
            if self.ambiguous:
                return None
            predicted, gate = self._prediction(now)       # hers from before the pass
        lost = self.state.lost
        same = next((t for t in tracks if t.id == self.state.target
                     and t.id not in self._others
                     and (not lost or self._confirmed_since_the_loss(t, now))), None)
        if same is not None and same.status == CONFIRMED:      # seen within lost_after (0.35 s)
            # while she is followed the same score decides whether her track is still her
            seen_score, looks_unlike = self._followed_score(same, predicted, gate, now)
            if seen_score >= score.THRESHOLD:
                same = self._untangle(same, tracks, now)
                if same is not None:
                    same = self._her_view_elsewhere(same, tracks, predicted, gate, now) or same
                    self._note_others(tracks, same.id, now)
                    return same
                if self.ambiguous:
                    return None           # two fit alike after a close pass: wait, decide again
                # none of the contestants is her: she is sought from where she was before it
                predicted, gate = self._prediction(now)
            elif looks_unlike:
                # the camera says her track is on somebody else now (someone who crossed her
                # close, hidden behind her until then): she is hidden, as at the last view of her
                self._others.add(same.id)
                self._views, self._views_of = [], None
                self._belief = self._matched or self._belief
                self._unmake_strangers_since(self._matched_t)
                predicted, gate = self._prediction(now)
        # who may be her: fresh confirmed tracks inside the gate (where she can have walked),
        # not seen as somebody else beside her (unless seen looking like her since), and
        # without her look, born where she could be; of those the identity score decides
        candidates = [t for t in tracks
                      if t.status == CONFIRMED and t.last_seen >= now - FRESH
                      and math.hypot(t.x - predicted[0], t.y - predicted[1]) <= gate
                      and (self._look_known or self._born_where_she_could_be(t))
                      and t.id not in self._strangers
                      and (not lost or self._confirmed_since_the_loss(t, now))
                      and (t.id not in self._others or self._seen_as_her_since_the_loss(t))]
        velocity = self._her_velocity(now)
        look = self._look if self._look_known else None
        choice, self.ambiguous = score.decide(
            [(score.identity_score(t, predicted, velocity, gate, look, since=self._belief.t), t)
             for t in candidates])
        return choice                    # None when two fit alike: wait, do not guess

    def _her_velocity(self, now: float) -> tuple[float, float]:
        """Her velocity as believed, for as long as the prediction uses it (`predict_for`)."""
        b = self._belief
        return (b.vx, b.vy) if now - b.t < self.params.predict_for else (0.0, 0.0)

    def _legs_alone(self, track, now: float) -> bool:
        """Her look is known and the camera has not seen this track for VIEW_SPEAKS_FOR s:
        only the laser says who carries it."""
        return self._look_known and (track.appearance_t is None
                                     or now - track.appearance_t > VIEW_SPEAKS_FOR)

    def _prediction(self, now: float) -> tuple[tuple[float, float], float]:
        """Where the belief puts her now, and the gate round it: it grows as far as she can
        have walked off the prediction (round a shelf end, into the next aisle); somebody
        else inside it is kept out by `_others` and by the rule that of two candidates one
        must be clearly nearer."""
        return (self._belief.at(now, self.params.predict_for),
                self._gate(now - self._belief.t))

    def _confirmed_since_the_loss(self, track, now: float) -> bool:
        """Once she has been unseen for LEGS_TRUSTED_FOR s, a track is taken for her only after
        a sensor that can tell a person (the camera; `Track.confirmed_seen`) has seen it since
        she was last seen: by then her coasting track's gate has grown so wide that the tracker
        re-attaches it to any legs near her prediction, and it took the wheels of a cart pushed
        behind another shopper, 1 m short of her, for her after 3 s (HOROS, bench_follow
        standin8 seed 2, issue 23). Sooner, legs alone still find her again: in a crowd the
        camera often cannot see her between the others (PERSES crowd10 seed 2 was given up)."""
        if now - self._belief.t <= LEGS_TRUSTED_FOR:
            return True
        return track.confirmed_seen is not None and track.confirmed_seen > self._belief.t

    @property
    def _look_known(self) -> bool:
        return self._look is not None and self._looks >= LOOK_KNOWN

    def _may_be_her(self, track) -> bool:
        """Once her look is known, only a track whose camera view scores as her (appearance
        log odds at least the score's THRESHOLD); before (or on a robot whose detector reports
        no appearance), one born where she could be."""
        if not self._look_known:
            return self._born_where_she_could_be(track)
        return (track.appearance is not None
                and score.appearance_score(track, self._look) >= score.THRESHOLD)

    def _seen_as_her_since_the_loss(self, track) -> bool:
        """The camera saw this track looking like her after she was lost: the tracker may
        have handed her an id that was somebody else's before (an id is not a person). A
        track found to be somebody's shadow needs a view since then: her belief goes back to
        before the close pass, and a view taken during it may be of either of them."""
        since = max(self._belief.t, self._shadowed.get(track.id, -math.inf))
        return (self._look_known and track.appearance_t is not None
                and track.appearance_t > since and self._may_be_her(track))

    def _followed_score(self, track, predicted, gate: float, now: float) -> tuple[float, bool]:
        """The identity score of her followed track this tick, and whether the camera's views
        of it say somebody else. Position is scored against `jump` (a track further off than
        that from where she was a tick ago scores below THRESHOLD: an id handed to somebody
        else), motion against her velocity, and appearance by the best of the track's recent
        views (the last MISMATCHES and any within UNLIKE_FOR s: two people at one spot make
        one track whose views alternate, and she is there while some look like her). While
        she is followed a view like her adds nothing (she is believed to be her already; a
        view cannot make an impossible jump possible); views unlike her count against. Her
        old id back after a loss is judged by its newest view instead, taken since the loss
        (a view from before counts only against), with someone close or not."""
        p = self.params
        self._note_view(track, now)
        b = self._belief
        position_and_motion = (score.position_score(track, predicted, max(gate, p.jump))
                               + score.motion_score(track, (b.vx, b.vy)))
        if self.state.lost and self._look_known:
            # her old id back after a loss: its newest view, if taken since, is evidence even
            # with someone close (the id came back 1 s after the loss on a crosser's legs, the
            # camera saw him, and the muted view let him be taken for her: bench_follow
            # crowd10 seed 9, PERSES, issue 23); a view from before the loss only against
            looks = score.appearance_score(track, self._look, since=b.t)
            return position_and_motion + min(looks, 0.0), looks < 0.0
        looks = self._recent_view_score(now)
        if looks is None or self._contest is not None:
            return position_and_motion, False   # no fresh view, or someone close: no evidence
        return position_and_motion + min(looks, 0.0), looks < 0.0

    def _note_view(self, track, now: float) -> None:
        """Learn her look from fresh camera views of her track while nobody is close to her,
        and keep each view's appearance score; remember her state at the last view like her."""
        if track.id != self._views_of:
            self._views, self._views_of = [], track.id     # another track: its own views
        fresh = (track.appearance is not None and track.appearance_t is not None
                 and track.appearance_t >= now - FRESH and track.appearance_t != self._look_t)
        if not fresh or self._contest is not None:
            return                  # someone close to her: the camera's view may be theirs
        self._look_t = track.appearance_t
        if not self._look_known:
            self._learn(track.appearance)
            self._matched, self._matched_t = self._belief, now
            return
        looks = score.appearance_score(track, self._look)
        self._views.append((now, looks))
        del self._views[:-VIEWS_KEPT]
        if looks >= score.THRESHOLD:
            self._matched, self._matched_t = self._belief, now
            self._learn(track.appearance)

    def _recent_view_score(self, now: float) -> float | None:
        """The best appearance score of her track's last MISMATCHES views and of those within
        UNLIKE_FOR s; None without any."""
        recent = [looks for k, (t, looks) in enumerate(reversed(self._views))
                  if k < MISMATCHES or now - t <= UNLIKE_FOR]
        return max(recent) if recent else None

    def _learn(self, seen) -> None:
        self._look = appearance.blend(self._look, seen, max(LOOK_WEIGHT, 1.0 / (self._looks + 1)))
        self._looks += 1

    def _gate(self, unseen: float) -> float:
        """How far from the prediction she can be after `unseen` s: the gate grows at walking
        pace, or at her own where she walks faster (a fast walker searched for far away)."""
        p = self.params
        growth = max(p.gate_growth, getattr(self, "_usual_pace", 0.0))
        return min(p.gate + growth * max(unseen, 0.0), p.max_gate)

    def _note_births(self, now: float) -> None:
        """Where each track was first seen: a track born far from where the customer could
        have been is somebody else (a shopper who came from behind the robot), whatever it
        does later; one born where a stranger was just seen is that stranger. Also where each
        stranger was last seen."""
        ids = set()
        tracks = self.perception.believed
        for t in tracks:
            ids.add(t.id)
            if t.id in self._strangers and t.status == CONFIRMED \
                    and t.last_seen >= now - FRESH:
                self._stranger_seen[t.id] = _Belief(t.x, t.y, t.vx, t.vy, t.last_seen)
        for t in tracks:
            if t.id not in self._first_seen:
                self._first_seen[t.id] = (now, t.x, t.y)
                if self._born_as_a_stranger(t, tracks, now):
                    self._make_stranger(t.id, now)
                    self._others.add(t.id)
        for gone in set(self._first_seen) - ids:
            del self._first_seen[gone]
        for gone in set(self._stranger_seen) - ids:
            if now - self._stranger_seen[gone].t > STRANGER_MEMORY:
                del self._stranger_seen[gone]

    def _born_as_a_stranger(self, track, tracks, now: float) -> bool:
        """A track born while a stranger's track is out of sight, where that stranger explains
        its birth place better than the customer does by score.MARGIN (log densities of the
        two predictions, each with its own gate: a stranger unseen for a moment is pinned
        down, she, unseen for seconds, may be anywhere in a wide gate). The search took a
        look-alike standing in an aisle for her after a loss: the look-alike's track had
        been given a new id, so the stranger rule had no hold on it (bench_follow lookalike
        seed 2, PERSES, issue 23)."""
        if self._belief is None or track.id == self.state.target:
            return False
        seen_now = {t.id for t in tracks if t.last_seen >= now - FRESH}
        p = self.params
        her = score.position_log_density(
            (track.x, track.y), self._belief.at(now, p.predict_for),
            self._gate(now - self._belief.t))
        for sid, s in self._stranger_seen.items():
            if sid in seen_now or sid == track.id:
                continue                    # the stranger is in view: this is someone else
            at, gate = s.at(now, p.predict_for), self._gate(now - s.t)
            if score.position_score(track, at, gate) < score.THRESHOLD:
                continue                    # not where the stranger can have got to
            if score.position_log_density((track.x, track.y), at, gate) - her >= score.MARGIN:
                return True
        return False

    def _born_where_she_could_be(self, track) -> bool:
        """A track first seen after the customer was last seen must have been born inside the
        gate of that moment (she reappears where she could have walked to)."""
        born = self._first_seen.get(track.id)
        if born is None or born[0] <= self._belief.t:
            return True
        at = self._belief.at(born[0], self.params.predict_for)
        reach = self._gate(born[0] - self._belief.t) + BIRTH_MARGIN
        return math.hypot(born[1] - at[0], born[2] - at[1]) <= reach

    def _note_others(self, tracks, target: int, now: float) -> None:
        """People seen at the same time as the customer are somebody else, for good; not those
        close to them, whose identity the tracker may just have swapped with theirs, nor one
        who looks like her (her track may be the one that passed to somebody else) unless her
        own track's views scored as her within UNLIKE_FOR s: then a look-alike seen apart from
        her is a stranger (`_strangers`), never taken for her, however like her it looks.
        Only a view of the last VIEW_SPEAKS_FOR s makes a track look like her: her old track,
        carried by legs alone onto a shopper's cart while she walked on unseen, kept her last
        view for 4 s beside her new track, stayed out of `_others`, and was taken for her when
        she was hidden again (bench_follow rude seed 2, PERSES, issue 23)."""
        confirmed_her = self._look_known and now - self._matched_t <= UNLIKE_FOR
        for t in tracks:
            if t.id == target or t.status != CONFIRMED or t.id in self._contest_ids:
                continue
            viewed_lately = (t.appearance_t is not None
                             and now - t.appearance_t <= VIEW_SPEAKS_FOR)
            if not (self._look_known and viewed_lately and self._may_be_her(t)):
                self._others.add(t.id)
            elif confirmed_her:
                self._others.add(t.id)
                self._make_stranger(t.id, now)

    def _make_stranger(self, track_id: int, now: float) -> None:
        self._strangers.setdefault(track_id, now)

    def _unmake_strangers_since(self, since: float) -> None:
        """Her followed track turned out to be somebody else: the tracks taken for strangers
        since her track's last view like her were judged against a track that was no longer
        hers, and one of them may be she. Her id passed to a crosser as he walked past her;
        for 0.3 s the camera's last view of that id was still of her, her own new track was
        taken for a look-alike seen apart from her, and the robot searched 26 s with her
        1.6-3.3 m away in view (bench_follow crowd10 seed 11, PERSES, issue 23)."""
        for track_id, when in list(self._strangers.items()):
            if when > since:
                del self._strangers[track_id]
                self._others.discard(track_id)
                self._stranger_seen.pop(track_id, None)

    def _untangle(self, target, tracks, now: float):
        """Two people passing within CONTEST_NEAR of each other can swap track ids. While
        someone is that close to the customer (`contestants`), remember where the customer was
        and how they moved before; when the two are apart again, the customer is the track
        nearest that prediction (one who stood still stayed, one who walked went on)."""
        near = contestants(target, tracks)
        if near:
            if self._shadows_another(target, tracks, now):
                return self._lost_to_shadow(target, now)
            if self._contest is None:
                b = self._belief
                standing = self._pace(target, now) < self.params.standing
                self._contest = _Belief(b.x, b.y, 0.0 if standing else b.vx,
                                        0.0 if standing else b.vy, b.t)
            for t in tracks:
                if t.id in near and t.id not in self._contest_ids:
                    self._contest_others[t.id] = self._as_they_came(t, now)
            self._contest_ids |= near
            return self._camera_settles(target, tracks, now)
        if self._contest is None:
            return target
        self._contest_ids.add(target.id)
        return self._settle(tracks, now)

    def _shadows_another(self, target, tracks, now: float) -> bool:
        """Her track, unseen by the camera for VIEW_SPEAKS_FOR s, lies within SHADOW_NEAR of
        a track whose latest view (within as long) is unlike her: one person the laser splits
        into two tracks (legs, a cart's wheels) and the camera sees as somebody else, not she
        beside them. Her hidden id slid onto a crosser's legs beside his own track while she
        stood unseen 0.6 m away (bench_follow crowd20 seed 3, HOROS), and onto a rude
        shopper's cart beside him while she walked off (rude seed 2, PERSES, issue 23); the
        robot followed each for about a second."""
        if not self._legs_alone(target, now):
            return False
        return any(t.id != target.id and t.status == CONFIRMED
                   and t.appearance_t is not None and now - t.appearance_t <= VIEW_SPEAKS_FOR
                   and math.hypot(t.x - target.x, t.y - target.y) < SHADOW_NEAR
                   and score.appearance_score(t, self._look) <= -score.MARGIN
                   for t in tracks)

    def _her_view_elsewhere(self, followed, tracks, predicted, gate: float, now: float):
        """While legs alone keep her followed track (no camera view for VIEW_SPEAKS_FOR s), a
        fresh view like her on another track near where she should be (as far as `jump`) is
        the better evidence: that track, when the one score prefers it by the margin, else
        None. Her old id, taken back on a crosser's legs after a short loss, was followed for
        0.9 s while the camera saw her, as a new track, 1 m from it (bench_follow crowd20
        seed 0, PERSES, issue 23). Never a stranger (a look-alike seen apart from her)."""
        if not self._legs_alone(followed, now):
            return None
        reach = max(gate, self.params.jump)
        rivals = [t for t in tracks if t.id != followed.id and t.status == CONFIRMED
                  and t.appearance_t is not None and now - t.appearance_t <= FRESH
                  and t.id not in self._strangers and t.id not in self._others
                  and math.hypot(t.x - predicted[0], t.y - predicted[1]) <= reach]
        if not rivals:
            return None
        velocity, since = self._her_velocity(now), self._belief.t
        choice, _ = score.decide(
            [(score.identity_score(t, predicted, velocity, reach, self._look, since=since), t)
             for t in (followed, *rivals)])
        if choice is None or choice is followed:
            return None
        self._swapped_from(followed.id)
        self._end_contest()
        return choice

    def _lost_to_shadow(self, target, now: float):
        """Her id is somebody else's shadow: she is hidden, sought from where she was before
        anybody came close (the contest's belief) and found again as after any loss."""
        self._others.add(target.id)
        self._shadowed[target.id] = now
        if self._contest is not None:
            self._belief = self._contest
        self._end_contest()
        return None

    def _camera_settles(self, target, tracks, now: float):
        """While someone is close to her, one view may be of either of them, so no single view
        counts (`_followed_score`); but CAMERA_SETTLES fresh views in a row of her followed
        track unlike her (by score.MARGIN), while exactly one other contestant's last as many
        are all like her, say that the ids swapped: she is taken back at once. A crosser
        standing 0.4 m from her took her id as she walked up to the robot, and the robot
        waited on him for 2.6 s while every view of him said somebody else and every view of
        her new track said her (bench_follow crowd20 seed 2, HOROS, issue 23). Never with a
        look-alike (a stranger) among them: his views are like her too, and her own track's
        views had turned unlike her for three views while he stood by; he was taken for her
        for 9 s (bench_follow lookalike seed 2, PERSES)."""
        if not self._look_known or self._contest_ids & self._strangers.keys():
            return target
        ids = self._contest_ids | {target.id}
        for t in tracks:
            if t.id in ids:
                self._note_contest_view(t)
        if not self._all_views(target.id, lambda s: s <= -score.MARGIN):
            return target
        like = [t for t in tracks if t.id in self._contest_ids and t.id != target.id
                and t.status == CONFIRMED
                and self._all_views(t.id, lambda s: s >= score.MARGIN)]
        if len(like) != 1:
            return target
        self._swapped_from(target.id)
        self._end_contest()
        return like[0]

    def _note_contest_view(self, track) -> None:
        """Keep a contestant's camera views (their time and appearance score), each once."""
        if track.appearance is None or track.appearance_t is None:
            return
        views = self._contest_views.setdefault(track.id, [])
        if views and views[-1][0] == track.appearance_t:
            return
        views.append((track.appearance_t, score.appearance_score(track, self._look)))
        del views[:-CAMERA_SETTLES]

    def _all_views(self, track_id: int, test) -> bool:
        views = self._contest_views.get(track_id, [])
        return len(views) >= CAMERA_SETTLES and all(test(s) for _, s in views)

    def _settle(self, tracks, now: float):
        """After a close pass, the contestant nearest where she should be (see `_untangle`),
        or None. While two fit alike the contest stays open (`_unsettled`) and is decided
        again each tick until one is clearly her or none fits: the robot waits meanwhile. A
        look-alike who walked close past her standing took her track's id, and the next tick
        took that id back as her (nothing compared it with the other contestant any more),
        so the robot followed the look-alike for 40 s (tests/skills/test_following.py, HOROS,
        with the robot waiting 5 cm further off). Her followed id carries CONTINUITY: without
        it two standing 0.8 m apart stayed undecided, and whoever stood still longer won
        (bench_follow lookalike seed 2, HOROS)."""
        before, ids = self._contest, self._contest_ids
        expected = before.at(now, self.params.predict_for)
        options = [t for t in tracks if t.id in ids and t.status == CONFIRMED]
        if self._unsettled and len(options) < len(ids):
            # one of two who fitted alike vanished (hidden by the other): the one left is not
            # her for that; she is lost, and found again as after any loss (the look-alike,
            # a stranger, never is; bench_follow lookalike seed 0, PERSES)
            self._unsettled = False
            self._end_contest()
            self._belief = before
            return None
        velocity = (before.vx, before.vy)
        look = self._look if self._look_known else None
        # a view from before they came close cannot tell whether the ids swapped since: it
        # counts only against (PERSES carts seed 4 kept her old id, left on a cart's wheels);
        # with a look-alike among them (seen apart from her, looking like her: a stranger)
        # no view tells them apart, and the camera's next view of one of them (whichever it
        # happens to see) must not decide: views count only against then (bench_follow
        # lookalike seed 5, PERSES: her track had no view since, the look-alike's had one)
        alike = look is not None and any(t.id in self._strangers for t in options)
        since = math.inf if alike else before.t
        followed = self.state.target
        scored = []
        for t in options:
            hers = (score.identity_score(t, expected, velocity, UNTANGLE_REACH, look, since=since)
                    + (CONTINUITY if t.id == followed else 0.0))
            rest = [o for o in options if o is not t]
            scored.append((hers, hers + self._others_explained(rest, now), t))
        best, ambiguous = score.decide_assignment(scored)
        self._unsettled = best is None and ambiguous
        if not self._unsettled:
            self._end_contest()
        if best is None:
            # none of them is where the customer should be (they are hidden: the track that
            # walked off with the id was somebody else), or two fit alike (a look-alike
            # beside her): she counts as lost until one of them is clearly her
            if not ambiguous and followed is not None:
                self._others.add(followed)
            self.ambiguous = ambiguous
            self._belief = before
            return None
        if best.id != followed:
            self._swapped_from(followed)
        return best

    def _swapped_from(self, followed: int | None) -> None:
        """Her id passed to somebody else: that id is somebody else now, and the pace
        measured on it was theirs."""
        self._recent = []
        if followed is not None:
            self._others.add(followed)
        self.state = replace(self.state, swaps=self.state.swaps + 1)

    def _as_they_came(self, track, now: float) -> _Belief:
        """Where a contestant was and how it moved when it came close to her (standing still
        if slower than `standing`, as she is remembered in `_untangle`)."""
        moving = math.hypot(track.vx, track.vy) >= self.params.standing
        return _Belief(track.x, track.y, track.vx if moving else 0.0,
                       track.vy if moving else 0.0, now)

    def _others_explained(self, rest, now: float) -> float:
        """How well the contestants other than the one taken for her are explained as the
        other people who came close (`_contest_others`), by the best one-to-one pairing:
        position scores against where each was predicted (their motion when they came close
        predicts where; it is not scored again: a track that jumped in a tick while
        reporting walking pace then outweighed her fresh view, PERSES carts seed 4's test).
        It is the other half of the settle's question: her followed track 0.13 m from where
        she stood and the look-alike's 0.7 m off fitted her alike (within the margin), though
        the look-alike stood exactly where he had stood all along; scored on her alone, the
        settle waited, and when she walked off took the look-alike for her by elimination and
        the robot stood by him for 174 s (bench_follow lookalike seed 10, HOROS, issue 23)."""
        people = list(self._contest_others.values())
        if not rest or not people:
            return 0.0
        horizon = self.params.predict_for

        def fit(track, person: _Belief) -> float:
            return score.position_score(track, person.at(now, horizon), UNTANGLE_REACH)

        if len(rest) <= len(people):
            pairings = ((rest, chosen) for chosen in itertools.permutations(people, len(rest)))
        else:
            pairings = ((chosen, people) for chosen in itertools.permutations(rest, len(people)))
        return max(sum(fit(t, person) for t, person in zip(tracks, persons))
                   for tracks, persons in pairings)

    def _end_contest(self) -> None:
        self._contest, self._contest_ids, self._contest_others = None, set(), {}
        self._contest_views = {}

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

    def _plausible(self, track, followed: bool = False) -> bool:
        """A person's centre cannot lie in or against a wall or shelf: a track there has been
        pulled onto a shelf corner or door post (laser legs) and is not the customer. Her own
        followed track keeps only FOLLOWED_CLEARANCE: a customer standing at a shelf has her
        centre 0.2 m from it, and the track's 0.1 m of jitter put it under PERSON_CLEARANCE
        several times a second; each time she counted as lost for a tick or two (dozens of
        losses while she stood at the shelf, benchmarks/bench_follow.py seed 2). Only while
        she is seen: once lost, her old id is a candidate like any other (the tracker slid
        one along the shelf ends, and the relaxed rule took it back as her)."""
        nav = self.navigation
        least = FOLLOWED_CLEARANCE if followed else PERSON_CLEARANCE
        return nav is None or bool(nav.grid.clearance_at(track.x, track.y) >= least)
