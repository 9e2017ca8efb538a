"""Simulated people: each follows its scenario script (walk, pause, approach the robot, answer
on the touch screen, wait to be called, leave), reacting to what the robot shows and says.

A person is a point that walks at its own speed; the sensors see it as a body circle (sonar,
bumpers) or as two swinging leg circles (laser), see `robots.sim.world`.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

from robots.sim.scenario import (Answer, Approach, Leave, Pause, PersonPlan, Point, Walk,
                                 WaitForCall)

if TYPE_CHECKING:
    from robots.sim.world import World

BODY_RADIUS = 0.2        # m, what sonar and bumpers hit
LEG_RADIUS = 0.06        # m
LEG_SPREAD = 0.125       # m, half the distance between the legs, across the heading
LEG_SWING = 0.1          # m, amplitude along the heading while walking
STRIDE = 1.2             # m walked per full leg cycle
ARRIVED = 0.02           # m, close enough to a waypoint
CALL_DISTANCE = 1.5      # m; what the robot says while the person is farther away is a call


class SimPerson:
    """One scripted person. `in_world` is False before `appear` and after `leave`."""

    def __init__(self, plan: PersonPlan, resolve: Callable[[Point], tuple[float, float]]) -> None:
        self.plan = plan
        self.id = plan.id
        self.resolve = resolve
        self.x, self.y = resolve(plan.at)
        self.heading = 0.0
        self.speed = 0.0              # m/s, current
        self.in_world = False
        self.gone = False             # has left for good
        self.phase = 0.0              # leg cycle, rad
        self.steps = list(plan.steps)
        self.index = -1               # current step; -1 before appearing
        self.step_started = 0.0
        self.step_state: dict = {}
        self.answered: set[str] = set()
        self.pressed: list[tuple[float, str, str]] = []   # (t, prompt_id, button), for tests
        self.calls_heard = 0          # utterances while away, since last near the robot
        self._utterances_seen = 0

    @property
    def current_step(self):
        """The step being carried out, or None (not yet appeared, done or gone)."""
        if 0 <= self.index < len(self.steps):
            return self.steps[self.index]
        return None

    def step(self, dt: float, world: "World") -> None:
        """Advance the script by dt seconds of sim time."""
        self.speed = 0.0
        if self.gone:
            return
        if not self.in_world:
            if world.t + 1e-9 < self.plan.appear:
                return
            self.in_world = True
            self._begin(0, world)
        self._listen(world)
        step = self.current_step
        if step is None:
            self._face_robot(world)
            return
        handler = _HANDLERS[type(step)]
        if handler(self, step, dt, world):
            self._begin(self.index + 1, world)

    def leg_positions(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """Left and right leg centres; the legs swing along the heading while walking."""
        c, s = math.cos(self.heading), math.sin(self.heading)
        swing = LEG_SWING * math.sin(self.phase)
        left = (self.x - s * LEG_SPREAD + c * swing, self.y + c * LEG_SPREAD + s * swing)
        right = (self.x + s * LEG_SPREAD - c * swing, self.y - c * LEG_SPREAD - s * swing)
        return left, right

    # -- helpers ---------------------------------------------------------------------------

    def _listen(self, world: "World") -> None:
        """Count what the robot said while the person was away (a call); near it, forget."""
        said = len(world.utterances) - self._utterances_seen
        self._utterances_seen = len(world.utterances)
        if self._distance_to_robot(world) <= CALL_DISTANCE:
            self.calls_heard = 0
        else:
            self.calls_heard += said

    def _begin(self, index: int, world: "World") -> None:
        self.index = index
        self.step_started = world.t
        self.step_state = {"utterances": len(world.utterances)}

    def _walk_towards(self, tx: float, ty: float, dt: float, stop_at: float = 0.0) -> bool:
        """Walk at the person's speed until `stop_at` from (tx, ty); True once there."""
        dx, dy = tx - self.x, ty - self.y
        distance = math.hypot(dx, dy)
        remaining = distance - stop_at
        if remaining <= ARRIVED:
            return True
        self.heading = math.atan2(dy, dx)
        travel = min(self.plan.speed * dt, remaining)
        self.x += dx / distance * travel
        self.y += dy / distance * travel
        self.speed = travel / dt
        self.phase = (self.phase + 2 * math.pi * travel / STRIDE) % (2 * math.pi)
        return remaining - travel <= ARRIVED

    def _face_robot(self, world: "World") -> None:
        body = world.body
        if (body.x, body.y) != (self.x, self.y):
            self.heading = math.atan2(body.y - self.y, body.x - self.x)

    def _distance_to_robot(self, world: "World") -> float:
        return math.hypot(world.body.x - self.x, world.body.y - self.y)

    def _leave_now(self, world: "World") -> None:
        """Give up on the script: walk to the exit and vanish."""
        self.steps = self.steps[:self.index + 1] + [Leave(None)]
        self._begin(self.index + 1, world)


def _walk(person: SimPerson, step: Walk, dt: float, world: "World") -> bool:
    state = person.step_state
    waypoint = state.setdefault("waypoint", 0)
    tx, ty = person.resolve(step.waypoints[waypoint])
    if person._walk_towards(tx, ty, dt):
        state["waypoint"] = waypoint + 1
    return state["waypoint"] >= len(step.waypoints)


def _pause(person: SimPerson, step: Pause, dt: float, world: "World") -> bool:
    return world.t - person.step_started >= step.seconds - 1e-9


def _approach(person: SimPerson, step: Approach, dt: float, world: "World") -> bool:
    """Walk straight at the robot's current position until `distance` from its centre."""
    arrived = person._walk_towards(world.body.x, world.body.y, dt, step.distance)
    if arrived:
        person._face_robot(world)
    return arrived


def _answer(person: SimPerson, step: Answer, dt: float, world: "World") -> bool:
    """Press the next button on each prompt not yet answered, `delay` s after it appeared."""
    state = person.step_state
    given = state.setdefault("given", 0)
    if given >= len(step.buttons):
        return True
    if world.t - person.step_started >= step.timeout:
        return True
    if person._distance_to_robot(world) > step.reach:
        person._walk_towards(world.body.x, world.body.y, dt, max(0.3, step.reach - 0.3))
        return False
    person._face_robot(world)
    screen = world.screen
    if screen.prompt is None:
        return False
    prompt_id = screen.prompt[0]
    if prompt_id in person.answered or world.t - screen.shown_at < step.delay - 1e-9:
        return False
    button = step.buttons[given]
    screen.press(prompt_id, button)
    person.answered.add(prompt_id)
    person.pressed.append((world.t, prompt_id, button))
    state["given"] = given + 1
    return state["given"] >= len(step.buttons)


def _wait_for_call(person: SimPerson, step: WaitForCall, dt: float, world: "World") -> bool:
    """Stand still until the robot calls (go on) or the timeout passes (leave). A call is an
    utterance after the step began, or one heard while walking away before it."""
    person._face_robot(world)
    if len(world.utterances) > person.step_state["utterances"] or person.calls_heard:
        return True
    if world.t - person.step_started >= step.timeout - 1e-9:
        person._leave_now(world)
    return False


def _leave(person: SimPerson, step: Leave, dt: float, world: "World") -> bool:
    tx, ty = person.resolve(step.to if step.to is not None else person.plan.exit)
    if person._walk_towards(tx, ty, dt):
        person.in_world = False
        person.gone = True
        person.index = len(person.steps)
    return False


_HANDLERS = {Walk: _walk, Pause: _pause, Approach: _approach, Answer: _answer,
             WaitForCall: _wait_for_call, Leave: _leave}
