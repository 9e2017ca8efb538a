"""py_trees leaves for going places and leading people: drive, lead, look back, call, ask to pass.

Like `behaviors.leaves`, each leaf cancels in `finish` what its `start` began, and only that,
so halting a GoTo or GuidePerson tree stops the navigation goal and ends the guide run once.
"""
from __future__ import annotations

import math

from py_trees.common import Status

from behaviors.leaves import SkillLeaf
from behaviors.registry import BehaviorContext
from skills.guiding import (GAVE_UP, LEADING, OUTCOME_ARRIVED, OUTCOME_NAVIGATION,
                            OUTCOME_USER_LOST, WAITING)
from skills.motion import Goal
from skills.navigation.navigation import ARRIVED as NAV_ARRIVED, BLOCKED, PAUSED, TURNING

BEHIND_GRACE = 1.0       # s the user must stay behind before the guide stops for them
RESUME_SLACK = 0.5       # m beyond the following distance at which the guide drives on
WAIT_SLACK = 1.5         # m beyond the following distance at which the guide stops
NO_PLACE = ("no place to go: the parameter 'place' was not set (its percept had no value or "
            "the database no row for it)")
STALL_CLEARED = 0.5      # m further along its path after which a blocked robot is past the stall


class Drive(SkillLeaf):
    """Drive to a place (or pose) with the navigation skill: SUCCESS on arrival, FAILURE with
    the skill's reason (the leaf's feedback message) when it fails."""

    def __init__(self, ctx: BehaviorContext, place, speed: float | None = None) -> None:
        super().__init__(f"Drive to {place}", ctx)
        self.place, self.speed = place, speed

    def start(self) -> None:
        if self.place is not None:
            self.skills.require("navigation").go_to(self.place, self.now, speed=self.speed)

    def update(self) -> Status:
        if self.place is None:
            self.feedback_message = NO_PLACE
            return Status.FAILURE
        status = self.skills.navigation.status
        if status.succeeded:
            return Status.SUCCESS
        if status.failed:
            self.feedback_message = status.reason
            return Status.FAILURE
        return Status.RUNNING

    def finish(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.place is not None:
            self.skills.navigation.cancel(self.now)


class AskToPass(SkillLeaf):
    """While the way is blocked by a person (a track within `near` m of what blocks it), say
    `text` (once per blocked episode, again every `every` s): people standing in the way step
    aside when asked. A wall corner or a box is not asked, nor a track that sits on a wall (a
    door jamb the leg detector took for legs). Never finishes."""

    def __init__(self, ctx: BehaviorContext, text: str, every: float = 10.0,
                 near: float = 0.6) -> None:
        super().__init__("AskToPass", ctx)
        self.text, self.every, self.near = text, every, near
        self._last: float | None = None

    def update(self) -> Status:
        navigation = self.skills.navigation
        if navigation.state.phase != BLOCKED:
            self._last = None
        if navigation.person_blocking(self.near) is None:
            return Status.RUNNING
        now = self.now
        speaking = self.skills.speech is not None and self.skills.speech.status.running
        if not speaking and (self._last is None or now - self._last >= self.every):
            self._last = now
            if self.skills.speech is not None:
                self.skills.speech.say(self.text, now)
        return Status.RUNNING


class Lead(SkillLeaf):
    """Lead the user to `place`: drive at `pace` while they keep up, stop when they fall more
    than `follow_distance` + 1.5 m behind (or are not seen) for a second, drive on when they
    are back within `follow_distance` + 0.5 m, give up after `give_up_after` s of waiting.

    SUCCESS on arrival; FAILURE when the user did not come (guide.user_lost) or navigation
    failed (navigation.failure), with the reason as feedback. With `turn_back` (a robot without
    a head) the robot turns round to look for the user (towards where it last saw them) once
    per wait; a robot with a head does so when it waits for a user it does not see at all:
    in a 1 m hallway the walls' echo hides a visitor standing more than about 1.8 m straight
    behind HOROS from every rear sonar (their readings are those of the empty hallway), and
    the pan-tilt head cannot look back there, so only the laser and camera turned round tell
    a visitor standing there from one who left. On the goal, turning to the place's heading, it
    arrives before it waits; while the way is blocked it does not wait for the user either (a stall ends as a navigation
    failure, not as a lost user). A stall the robot has not driven past (`Stall`) is what it
    reports if it gives up waiting: held up in a door, ARGOS turned round to look for its
    visitor, on turning back the way was for a moment clear, it stopped for the visitor and the
    run ended as "user lost", which hid the stall."""

    def __init__(self, ctx: BehaviorContext, place: str, *, pace: float | None,
                 follow_distance: float, give_up_after: float, turn_back: bool) -> None:
        super().__init__(f"Lead to {place}", ctx)
        self.place, self.pace = place, pace
        self.follow_distance, self.give_up_after = follow_distance, give_up_after
        self.turn_back = turn_back
        self._behind_since: float | None = None
        self._turned = False
        self._stall = Stall()

    def start(self) -> None:
        if self.place is None:
            return
        skills, now = self.skills, self.now
        user = skills.perception.user
        skills.require("guide").start(self.place, now, user.id if user is not None else None)
        skills.require("navigation").go_to(self.place, now, speed=self.pace, lead=True)
        self._behind_since, self._turned = None, False
        self._stall = Stall()

    def update(self) -> Status:
        if self.place is None:
            self.feedback_message = NO_PLACE
            return Status.FAILURE
        skills, now = self.skills, self.now
        nav, guide = skills.navigation, skills.guide
        if nav.status.succeeded:
            return self._on_the_goal(now)
        if nav.status.failed:
            guide.finish(OUTCOME_NAVIGATION, now, nav.status.reason)
            self.feedback_message = nav.status.reason
            return Status.FAILURE
        self._stall.note(nav.state, nav.status.reason)
        state = guide.state
        distance = state.user_distance
        if state.phase == LEADING:
            behind = distance is None or distance > self.follow_distance + WAIT_SLACK
            # on the goal it arrives first; held up, it leaves nobody behind: the stall is the
            # navigation's to report (blocked, then failed), never a visitor lost
            if not behind or nav.state.phase in (TURNING, BLOCKED):
                self._behind_since = None
            elif self._behind_since is None:
                self._behind_since = now
            elif now - self._behind_since >= BEHIND_GRACE:
                nav.pause(now)
                guide.wait(now)
                self._turned = False
        elif state.phase == WAITING:
            if distance is not None and distance <= self.follow_distance + RESUME_SLACK:
                self._behind_since = None
                guide.lead(now)
                nav.resume(now)
            else:
                return self._keep_waiting(now, distance)
        elif state.phase == GAVE_UP:
            return Status.FAILURE
        return Status.RUNNING

    def _on_the_goal(self, now: float) -> Status:
        """Arrived: done with the user there. With the user not seen, or more than
        `follow_distance` + WAIT_SLACK away, for BEHIND_GRACE (a user who walked off while the
        robot drove its last metres), it waits there as on the way (turning round to look,
        without a head), and gives up after `give_up_after`. Arrival was done at once before:
        led a little faster, HOROS said "Here we are" to nobody, its user gone 2.5 s before."""
        guide = self.skills.guide
        state = guide.state
        distance = state.user_distance
        slack = RESUME_SLACK if state.phase == WAITING else WAIT_SLACK
        if distance is not None and distance <= self.follow_distance + slack:
            guide.finish(OUTCOME_ARRIVED, now, self.skills.navigation.status.reason)
            return Status.SUCCESS
        if state.phase == LEADING:
            if self._behind_since is None:
                self._behind_since = now
            if now - self._behind_since >= BEHIND_GRACE:
                guide.wait(now)
                self._turned = False
            return Status.RUNNING
        return self._keep_waiting(now, distance)

    def _keep_waiting(self, now: float, distance: float | None) -> Status:
        """Waiting for the user (on the way or on the goal): give up after `give_up_after`,
        else look round once."""
        if self.skills.guide.state.waiting_for >= self.give_up_after:
            return self._give_up(now)
        if self._may_look_round(distance):
            self._look_round(now)
        return Status.RUNNING

    def _may_look_round(self, distance: float | None) -> bool:
        """Once per wait: always without a head; with one, only for a user not seen at all."""
        return not self._turned and (self.turn_back or distance is None)

    def _give_up(self, now: float) -> Status:
        """Give up waiting: the user did not follow, unless the robot never got past a stall
        before it stopped for them; then the stall is what failed (navigation failed). On the
        goal the robot got where it was going: a stall on the way is no reason there."""
        distance = self.skills.guide.state.user_distance
        seen = "not seen" if distance is None else f"{distance:.1f} m away"
        waited = f"{seen} after waiting {self.skills.guide.state.waiting_for:.0f} s"
        nav = self.skills.navigation
        stall = "" if nav.status.succeeded else self._stall.reason   # on the goal: past it
        nav.cancel(now)
        if stall:
            reason = (f"{stall}, not driven past before the robot stopped for "
                      f"the user ({waited})")
            self.skills.guide.finish(OUTCOME_NAVIGATION, now, reason)
        else:
            reason = f"the user did not follow: {waited}"
            self.skills.guide.finish(OUTCOME_USER_LOST, now, reason)
        self.feedback_message = reason
        return Status.FAILURE

    def _look_round(self, now: float) -> None:
        """Turn the body to face back along the way it came (the camera and laser then see the
        user); navigation drives on from there when the user is back (it turns first)."""
        pose = self.skills.localization.state
        if pose is None or self.skills.navigation.state.phase not in (PAUSED, NAV_ARRIVED):
            return
        self._turned = True
        target = self.skills.guide.state.user_xy
        bearing = (math.atan2(target[1] - pose.y, target[0] - pose.x) if target is not None
                   else pose.th + math.pi)
        self.skills.motion.start(Goal("turn_to", bearing=bearing), now)

    def finish(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.place is not None:
            self.skills.navigation.cancel(self.now)
            self.skills.guide.cancel(self.now)


class Stall:
    """The last time navigation was held up (BLOCKED) on this run, until the robot has driven
    STALL_CLEARED m further along its path: a stall it has not driven past."""

    def __init__(self) -> None:
        self.reason = ""                    # the navigation's status then ("blocked for …")
        self._left = math.inf               # m of path left where it was held up

    def note(self, state, status_reason: str) -> None:
        """Look at the navigation's state of this tick."""
        if state.phase == BLOCKED:
            self.reason = status_reason or "blocked"
            self._left = state.distance_left
        elif self.reason and state.distance_left < self._left - STALL_CLEARED:
            self.reason, self._left = "", math.inf


class LookBack(SkillLeaf):
    """Keep the pan-tilt head on the follower (or straight back when unseen); never finishes."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("LookBack (head)", ctx)

    def update(self) -> Status:
        skills = self.skills
        pose, guide = skills.localization.state, skills.guide
        if pose is not None and guide is not None and guide.active:
            target = guide.state.user_xy or (pose.x - math.cos(pose.th), pose.y - math.sin(pose.th))
            skills.require("head").look_at(target, self.now)
        return Status.RUNNING

    def finish(self, new_status: Status) -> None:
        self.skills.head.center(self.now)


class CallWhileWaiting(SkillLeaf):
    """While the guide waits for the user, say `text` when it stops and every `every` s.
    Never finishes."""

    def __init__(self, ctx: BehaviorContext, text: str, every: float = 8.0) -> None:
        super().__init__("CallWhileWaiting", ctx)
        self.text, self.every = text, every
        self._last: float | None = None

    def update(self) -> Status:
        guide, now = self.skills.guide, self.now
        if guide is None or guide.state.phase != WAITING:
            self._last = None
            return Status.RUNNING
        speech = self.skills.speech
        if speech is not None and not speech.status.running and (
                self._last is None or now - self._last >= self.every):
            self._last = now
            speech.say(self.text, now)
        return Status.RUNNING
