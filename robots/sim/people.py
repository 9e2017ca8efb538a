"""Simulated people: each follows its scenario script (walk, pause, approach the robot, answer
on the touch screen, wait to be called, leave; follow the robot, make way for it, shop, lead
the robot), reacting to what the robot shows and says and to where it drives.

A person is a point that walks at its own speed; the sensors see it as a body circle (sonar,
bumpers) or as two swinging leg circles (laser), see `robots.sim.world`.

The script says where a person wants to go; how they get there among others (avoiding each
other, walls, carts and the robot, never overlapping) is `robots.sim.crowd`'s social forces,
unless the scenario scripts exact paths (`motion = "scripted"`). A person who yields to the
robot (`yielding` >= 0.5, a trait drawn per person, or `give_way = true`): while walking
under their own steam (`walk`, `leave`, the walks of `shop`) they stand while the robot is in
their way, as shoppers do, see `SimPerson._gives_way`. Steps whose point is the robot never give way:
`approach` and `answer` walk up to it, `follow` and `lead` keep their distance to it by their
own rules, `make_way` is already the stepping aside; standing steps have nothing to give.
A person leading the robot (`lead`) who hears it ask her to wait slows down, waits or walks
on as her drawn `heeding` says (`robots.sim.heeding`).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np

from robots.sim import letting_pass, visitors
from robots.sim.scenario import (Answer, Approach, Follow, Lead, Leave, MakeWay, Pause,
                                 PersonPlan, Point, Shop, Sync, Walk, WaitForCall)

if TYPE_CHECKING:
    from robots.sim.world import World

BODY_RADIUS = 0.2        # m, what sonar and bumpers hit
LEG_RADIUS = 0.06        # m
LEG_SPREAD = 0.125       # m, half the distance between the legs, across the heading
LEG_SWING = 0.1          # m, amplitude along the heading while walking
STRIDE = 1.2             # m walked per full leg cycle
ARRIVED = 0.02           # m, close enough to a waypoint
CART_RADIUS = 0.28       # m; a cart is two circles ahead of the person who pushes it
CART_OFFSETS = (0.5, 0.95)   # m ahead of the person's centre
CART_TURN_RATE = math.radians(90.0)   # rad/s a pushed cart turns at most
CALL_DISTANCE = 1.5      # m; what the robot says while the person is farther away is a call
FOLLOW_GAIN = 1.0        # 1/s: a follower walks faster by this much per metre too far behind
ROBOT_STILL = 1.0        # s the robot stands before a lagging follower closes up
CAUGHT_UP = 0.3          # m beyond the following distance that still counts as caught up
GOAL_RADIUS = 1.0        # m from a follow step's goal that counts as arrived
MIN_TRAIL = 1.0          # m the robot must drive before a follow step without goal can end
HOP = 1.0                # m; a follower cuts to a later breadcrumb this near, in the clear
HOP_LOOKAHEAD = 400      # breadcrumbs (40 m of trail) searched for such a cut
GIVE_WAY_AHEAD = 1.2     # m from the person's front (their cart's) to the robot's footprint
GIVE_WAY_MARGIN = 0.15   # m beside the person's (or cart's) width that still counts as the lane
GIVE_WAY_PATIENCE = 6.0  # s a person with give_way stands, then walks on regardless
YIELDS = 0.5             # a person whose yielding trait reaches this stands for the robot
BLOCKED_PATIENCE = 1.5   # s held up by others before a nearby waypoint counts as reached
NEAR_ENOUGH = 0.8        # m from a waypoint that counts as reached once held up


class SimPerson:
    """One scripted person. `in_world` is False before `appear` and after `leave`."""

    def __init__(self, plan: PersonPlan, resolve: Callable[[Point], tuple[float, float]],
                 rng: np.random.Generator | None = None) -> None:
        self.plan = plan
        self.rng = rng if rng is not None else np.random.default_rng(0)   # shop's draws
        self.id = plan.id
        self.resolve = resolve
        self.x, self.y = resolve(plan.at)
        self.heading = 0.0
        self.cart_heading = 0.0       # the cart points where the person last walked
        self.cart_turn_way = 0        # +1 / -1: turning the cart the long way round (blocked)
        self._cart_circles: tuple | None = None   # (x, y, cart heading), circles
        self.speed = 0.0              # m/s, current
        self.in_world = False
        self.gone = False             # has left for good
        self.phase = 0.0              # leg cycle, rad
        self.steps = list(plan.steps)
        self.index = -1               # current step; -1 before appearing
        self.step_started = 0.0
        self.step_state: dict = {}
        self.answered: set[tuple[str, float]] = set()   # (prompt id, when it was shown)
        self.pressed: list[tuple[float, str, str]] = []   # (t, prompt_id, button), for tests
        self.calls_heard = 0          # utterances while away, since last near the robot
        self._utterances_seen = 0
        self.waiting_since: float | None = None   # giving way to the robot since (sim s)
        self._looked = False          # the step checked for the robot in the way (give_way)
        self.yielding = (plan.yielding if plan.yielding is not None    # 0 .. 1, see
                         else 1.0 if plan.give_way else 0.0)          # robots.sim.crowd
        self.blocked_for = 0.0        # s held up by others (robots.sim.crowd)
        self.wished = 0.0             # m/s the script wanted to walk in the last substep
        self.heeding = None           # robots.sim.heeding.Listener: does she wait when asked
        self.aside: letting_pass.Aside | None = None     # letting the robot pass

    @property
    def current_step(self):
        """The step being carried out, or None (not yet appeared, done or gone)."""
        if 0 <= self.index < len(self.steps):
            return self.steps[self.index]
        return None

    def due(self, t: float) -> bool:
        """Whether the plan's time to appear has come."""
        return t + 1e-9 >= self.plan.appear

    def step(self, dt: float, world: "World") -> None:
        """Advance the script by dt seconds of sim time."""
        self.speed = 0.0
        if self.gone:
            return
        appearing = not self.in_world
        if appearing:
            if not self.due(world.t):
                return
            self.in_world = True
            self._begin(0, world)
        heard = self._listen(world)
        step = self.current_step
        if step is None:
            self._face_robot(world)
            return
        if heard and self.yielding >= YIELDS:
            letting_pass.listen(self, heard, world)
        self._looked = False
        if letting_pass.carry_on(self, dt, world):
            done = False
        else:
            done = _HANDLERS[type(step)](self, step, dt, world)
        if not self._looked:          # not walking on their own: a later wait starts afresh
            self.waiting_since = None
        if self.plan.cart:              # (nobody else has a cart to point)
            if appearing:
                self.cart_heading = self.heading
            elif self.speed > 0.0:
                self.steer_cart(dt)
        if done:
            self._begin(self.index + 1, world)

    def steer_cart(self, dt: float) -> None:
        """Turn the cart towards where the person walks, at most CART_TURN_RATE: a cart set
        to the walking heading at once swung its far end 0.58 m in a tick when a swerve of
        a few cm/s turned its pusher, into a robot braking beside it (bench_follow crowd20
        seed 6, PERSES, issue 23). After the short way swung the cart into somebody or the
        robot (`block_cart_turn`), it turns the other way round, as a shopper whose cart is
        against something does."""
        if self.aside is not None:
            return                    # pushed aside to let the robot pass: it keeps its heading
        turn = math.remainder(self.heading - self.cart_heading, math.tau)
        if self.cart_turn_way and turn * self.cart_turn_way < 0.0:
            turn += math.tau * self.cart_turn_way            # the long way round
        most = CART_TURN_RATE * dt
        step = max(-most, min(most, turn))
        self.cart_heading += step
        if abs(turn - step) < 1e-9:
            self.cart_turn_way = 0                          # the cart points her way again

    def block_cart_turn(self, turned: float) -> None:
        """The cart's turn of `turned` rad this substep swung it into something: turn the
        other way round from now on; if that way is blocked too, try the short way again."""
        if turned == 0.0:
            return
        way = -1 if turned > 0.0 else 1
        self.cart_turn_way = way if self.cart_turn_way == 0 else 0

    def hold_back(self, x: float, y: float, heading: float, cart_heading: float) -> None:
        """Undo this substep's appearing (there was no room after all): back to not yet in
        the world, at the spot they appear at; they try again next substep."""
        self.x, self.y, self.heading, self.cart_heading = x, y, heading, cart_heading
        self.in_world = False
        self.index = -1
        self.speed = 0.0
        self.step_state = {}

    def leg_positions(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """Left and right leg centres; the legs swing along the heading while walking."""
        c, s = math.cos(self.heading), math.sin(self.heading)
        swing = LEG_SWING * math.sin(self.phase)
        left = (self.x - s * LEG_SPREAD + c * swing, self.y + c * LEG_SPREAD + s * swing)
        right = (self.x + s * LEG_SPREAD - c * swing, self.y - c * LEG_SPREAD - s * swing)
        return left, right

    def cart_circles(self) -> list[tuple[float, float, float]]:
        """The cart as (x, y, r) circles (none without a cart): it turns only while walking,
        not when the person turns to a shelf or to the robot."""
        if not self.plan.cart:
            return []
        key = (self.x, self.y, self.cart_heading)    # asked for several times a substep
        if self._cart_circles is None or self._cart_circles[0] != key:
            self._cart_circles = (key, self._cart_at(self.cart_heading))
        return self._cart_circles[1]

    def _cart_at(self, heading: float) -> list[tuple[float, float, float]]:
        c, s = math.cos(heading), math.sin(heading)
        return [(self.x + c * d, self.y + s * d, CART_RADIUS) for d in CART_OFFSETS]

    # -- helpers ---------------------------------------------------------------------------

    def circles(self, cart_heading: float | None = None) -> list[tuple[float, float, float]]:
        """Their body and their cart's circles, (x, y, r); with `cart_heading`, the cart's
        as if it pointed there."""
        carts = (self.cart_circles() if cart_heading is None or not self.plan.cart
                 else self._cart_at(cart_heading))
        return [(self.x, self.y, BODY_RADIUS), *carts]

    def turn_cart_to(self, heading: float, dt: float) -> None:
        """Turn the cart towards `heading`, at most CART_TURN_RATE (pulled in along the
        robot's lane to let it pass, `robots.sim.letting_pass`)."""
        most = CART_TURN_RATE * dt
        turn = math.remainder(heading - self.cart_heading, math.tau)
        self.cart_heading += max(-most, min(most, turn))

    def _listen(self, world: "World") -> list[tuple[float, str]]:
        """Count what the robot said while the person was away (a call); near it, forget.
        What was said since the last substep, (sim s, words)."""
        heard = world.utterances[self._utterances_seen:]
        self._utterances_seen = len(world.utterances)
        if self._distance_to_robot(world) <= CALL_DISTANCE:
            self.calls_heard = 0
        else:
            self.calls_heard += len(heard)
        return heard

    def _begin(self, index: int, world: "World") -> None:
        self.index = index
        self.step_started = world.t
        self.step_state = {"utterances": len(world.utterances)}

    def _called(self, world: "World") -> bool:
        """The robot said something since this step began, or called while the person was
        away (the rule of `wait_for_call`)."""
        return len(world.utterances) > self.step_state["utterances"] or self.calls_heard > 0

    def _walk_path(self, path: list[tuple[float, float]], index: int, travel: float,
                   dt: float, world: "World | None" = None) -> int:
        """Walk up to `travel` metres along `path[index:]`; the index of the next point. With
        `world`, a person with give_way stands instead while the robot is in their way."""
        if world is not None and index < len(path) and self._gives_way(*path[index], world):
            return index
        moved = 0.0
        while index < len(path) and travel - moved > 1e-12:
            tx, ty = path[index]
            dx, dy = tx - self.x, ty - self.y
            gap = math.hypot(dx, dy)
            if gap > 1e-9:
                self.heading = math.atan2(dy, dx)
            if self._near_enough(gap):
                index += 1
                break
            if gap <= travel - moved:
                self.x, self.y = tx, ty
                moved += gap
                index += 1
            else:
                share = (travel - moved) / gap
                self.x += dx * share
                self.y += dy * share
                moved = travel
        self.speed = moved / dt
        self.phase = (self.phase + 2 * math.pi * moved / STRIDE) % (2 * math.pi)
        return index

    def _route_to(self, where: Point, world: "World") -> list[tuple[float, float]]:
        return world.route((self.x, self.y), self.resolve(where))

    def _face_place(self, where: Point, world: "World") -> None:
        """Face a named place's heading (a shelf, a door); points have none."""
        if isinstance(where, str):
            self.heading = world.floor.place(where)[2]

    def _walk_towards(self, tx: float, ty: float, dt: float, stop_at: float = 0.0,
                      world: "World | None" = None) -> bool:
        """Walk at the person's speed until `stop_at` from (tx, ty); True once there. With
        `world`, a person with give_way stands instead while the robot is in their way."""
        dx, dy = tx - self.x, ty - self.y
        distance = math.hypot(dx, dy)
        remaining = distance - stop_at
        if remaining <= ARRIVED or self._near_enough(remaining):
            return True
        if world is not None and remaining <= NEAR_ENOUGH and _robot_on(tx, ty, world):
            return True               # the robot stands on the spot: stand next to it
        if world is not None and self._gives_way(tx, ty, world):
            return False
        self.heading = math.atan2(dy, dx)
        travel = min(self.plan.speed * dt, remaining)
        self.x += dx / distance * travel
        self.y += dy / distance * travel
        self.speed = travel / dt
        self.phase = (self.phase + 2 * math.pi * travel / STRIDE) % (2 * math.pi)
        return remaining - travel <= ARRIVED

    def _near_enough(self, remaining: float) -> bool:
        """Held up by others for a while this near the waypoint: it counts as reached (the
        shelf or the spot is taken; people queue rather than push)."""
        if self.blocked_for >= BLOCKED_PATIENCE and remaining <= NEAR_ENOUGH:
            self.blocked_for = 0.0        # the next waypoint is waited for afresh
            return True
        return False

    def _gives_way(self, tx: float, ty: float, world: "World") -> bool:
        """True while a person with give_way, about to walk to (tx, ty), stands for the robot:
        it is in their way (`_robot_in_way`) and they have stood less than `GIVE_WAY_PATIENCE`
        (a person cannot wait forever when the robot waits for them too). They go on as soon
        as it is out of their way; after the patience they walk on as people without give_way
        do, until it is out of their way once. Standing looks like a pause: speed 0, legs
        still, facing where they were going (the cart turns only while walking)."""
        if self.yielding < YIELDS:
            return False
        self._looked = True
        if not self._robot_in_way(tx, ty, world):
            self.waiting_since = None
            return False
        if self.waiting_since is None:
            self.waiting_since = world.t
        if world.t - self.waiting_since >= GIVE_WAY_PATIENCE - 1e-9:
            return False
        if (tx, ty) != (self.x, self.y):
            self.heading = math.atan2(ty - self.y, tx - self.x)
        return True

    def _robot_in_way(self, tx: float, ty: float, world: "World") -> bool:
        """The robot's footprint is ahead along the way to (tx, ty), within `GIVE_WAY_AHEAD`
        of the person's front (the cart's front when they push one) and no farther than the
        way goes, and inside the lane: its centre nearer the line walked than the robot's
        radius plus the person's half width (the cart's, if wider) plus `GIVE_WAY_MARGIN`."""
        dx, dy = tx - self.x, ty - self.y
        length = math.hypot(dx, dy)
        if length <= 1e-9:
            return False
        ux, uy = dx / length, dy / length
        body = world.body
        rx, ry = body.x - self.x, body.y - self.y
        along = rx * ux + ry * uy
        across = abs(ry * ux - rx * uy)
        if self.plan.cart:
            front = max(CART_OFFSETS) + CART_RADIUS
            half_width = max(BODY_RADIUS, CART_RADIUS)
        else:
            front, half_width = BODY_RADIUS, BODY_RADIUS
        ahead = min(GIVE_WAY_AHEAD, length + GIVE_WAY_MARGIN)
        return (along > 0.0 and along - body.radius - front <= ahead
                and across < body.radius + half_width + GIVE_WAY_MARGIN)

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


def _robot_on(x: float, y: float, world: "World") -> bool:
    """The robot's footprint leaves no room for a person's body at (x, y): a spot a person
    wanted to stand on is taken (they stand next to it, as they do where others stand)."""
    body = world.body
    return math.hypot(x - body.x, y - body.y) < body.radius + BODY_RADIUS


def _walk(person: SimPerson, step: Walk, dt: float, world: "World") -> bool:
    state = person.step_state
    if step.route:
        return _walk_routed(person, list(step.waypoints), dt, world, give_way=True)
    waypoint = state.setdefault("waypoint", 0)
    tx, ty = person.resolve(step.waypoints[waypoint])
    if person._walk_towards(tx, ty, dt, world=world):
        state["waypoint"] = waypoint + 1
    return state["waypoint"] >= len(step.waypoints)


def _pause(person: SimPerson, step: Pause, dt: float, world: "World") -> bool:
    return world.t - person.step_started >= step.seconds - 1e-9


def _approach(person: SimPerson, step: Approach, dt: float, world: "World") -> bool:
    """Walk straight at the robot's current position until `distance` from its centre, or
    until touching its outline: people walk up to a robot, they do not push it (a `distance`
    its body does not leave room for, or a robot backing away slower than she walks, had her
    pressed against it for as long as it backed)."""
    touching = world.body.gap_to_circle(person.x, person.y, BODY_RADIUS) <= ARRIVED
    arrived = touching or person._walk_towards(world.body.x, world.body.y, dt, step.distance)
    if arrived:
        person._face_robot(world)
    return arrived


def _answer(person: SimPerson, step: Answer, dt: float, world: "World") -> bool:
    """Press the next button on each showing of a prompt not yet answered, `delay` s after it
    appeared (a question the robot asks again, "another one?", is answered again); on a typed
    prompt a value that is not a button is typed, `typing` s per character more."""
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
    prompt_id, _, buttons = screen.prompt
    button = step.buttons[given]
    delay = step.delay
    if screen.typed and button not in buttons:
        delay += step.typing * len(button)        # typing takes longer than a press
    showing = (prompt_id, screen.shown_at)      # a question asked again is a new showing
    if showing in person.answered or world.t - screen.shown_at < delay - 1e-9:
        return False
    screen.press(prompt_id, button)
    person.answered.add(showing)
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
    target = step.to if step.to is not None else person.plan.exit
    if step.route:
        there = _walk_routed(person, [target], dt, world, give_way=True)
    else:
        there = person._walk_towards(*person.resolve(target), dt, world=world)
    if there:
        person.in_world = False
        person.gone = True
        person.index = len(person.steps)
    return False


def _walk_routed(person: SimPerson, targets: list[Point], dt: float, world: "World",
                 give_way: bool = False, speed: float | None = None) -> bool:
    """Walk to each target in turn around walls (`world.route`) at `speed` (None: the
    person's own); True once at the last. With `give_way` the person gives way to the robot
    if their plan says so."""
    state = person.step_state
    target = state.setdefault("target", 0)
    if target >= len(targets):
        return True
    if "path" in state and person.blocked_for >= BLOCKED_PATIENCE and not world.walkable(
            (person.x, person.y), state["path"][min(state["next"], len(state["path"]) - 1)]):
        del state["path"]             # pushed off the way behind a shelf: find it again
    if "path" not in state:
        state["path"], state["next"] = person._route_to(targets[target], world), 0
    pace = person.plan.speed if speed is None else speed
    state["next"] = person._walk_path(state["path"], state["next"], pace * dt, dt,
                                      world if give_way else None)
    if state["next"] >= len(state["path"]):
        state["target"] = target + 1
        del state["path"]
    return state["target"] >= len(targets)


def _follow(person: SimPerson, step: Follow, dt: float, world: "World") -> bool:
    """Walk along the robot's trail, `distance` behind it (plus `lag` while it drives), at
    most at the person's speed; stop once, give up, or end when the robot has arrived."""
    state, now = person.step_state, world.t
    if now - person.step_started >= step.timeout - 1e-9:
        return True
    if "started" not in state:
        if step.after_call and not person._called(world):
            person._face_robot(world)
            return False
        state.update(started=now, next=len(world.trail) - 1, first=len(world.trail) - 1,
                     walked=0.0, stop=None)
    if now - state["started"] >= step.until - 1e-9:
        return True
    if _follow_stopped(person, step, state, now):
        return False
    trail, cumulative = world.trail, world.trail_lengths
    index = state["next"] = _shortcut(person, trail, state["next"], world)
    tx, ty = trail[index]
    path = (math.hypot(tx - person.x, ty - person.y) + cumulative[-1] - cumulative[index]
            + math.hypot(world.body.x - trail[-1][0], world.body.y - trail[-1][1]))
    robot_still = world.robot_still_for >= ROBOT_STILL
    target = step.distance + (0.0 if robot_still else step.lag)
    if _follow_arrived(person, step, state, world, path):
        return True
    behind = path - target
    if behind <= ARRIVED or person._distance_to_robot(world) <= step.distance:
        person._face_robot(world)
        return False
    pace = min(person.plan.speed, abs(world.body.v) + FOLLOW_GAIN * behind)
    before = (person.x, person.y)
    state["next"] = person._walk_path(trail, index, min(pace * dt, behind), dt)
    state["next"] = min(state["next"], len(trail) - 1)
    state["walked"] += math.hypot(person.x - before[0], person.y - before[1])
    return False


def _shortcut(person: SimPerson, trail: list, index: int, world: "World") -> int:
    """The latest breadcrumb within `HOP` of the person that a straight line reaches with
    the walking clearance (the follower joins or cuts back to the trail), else `index`."""
    ahead = np.asarray(trail[index:index + HOP_LOOKAHEAD])
    near = np.flatnonzero(np.hypot(ahead[:, 0] - person.x, ahead[:, 1] - person.y) <= HOP)
    for offset in near[::-1][:4]:
        if offset == 0:
            break
        if world.walkable((person.x, person.y), trail[index + int(offset)]):
            return index + int(offset)
    return index


def _follow_stopped(person: SimPerson, step: Follow, state: dict, now: float) -> bool:
    """True while the person stands in the one stop of `stop_after`/`stop_after_m`."""
    if state["stop"] is None:
        due = (now - state["started"] >= step.stop_after - 1e-9
               or state["walked"] >= step.stop_after_m - 1e-9)
        if not due:
            return False
        state["stop"] = now
    if state["stop"] is not False and now - state["stop"] < step.stop_for - 1e-9:
        return True
    state["stop"] = False          # stopped and came on: never again in this step
    return False


def _follow_arrived(person: SimPerson, step: Follow, state: dict, world: "World",
                    path: float) -> bool:
    """The robot has stood `settle` s (at its goal, or after driving) while the person was
    caught up: the tour is over. (A guide waiting for a lagging person drives on as soon as
    they are near, so it does not stand that long with them caught up.)"""
    if path > step.distance + CAUGHT_UP:
        state["caught_up"] = None
        return False
    if state.get("caught_up") is None:
        state["caught_up"] = world.t
    if min(world.robot_still_for, world.t - state["caught_up"]) < step.settle - 1e-9:
        return False
    body = world.body
    if step.goal is not None:
        gx, gy = person.resolve(step.goal)
        return math.hypot(body.x - gx, body.y - gy) <= GOAL_RADIUS
    lengths = world.trail_lengths
    return lengths[-1] - lengths[state["first"]] >= MIN_TRAIL


def _make_way(person: SimPerson, step: MakeWay, dt: float, world: "World") -> bool:
    """Stand until the robot, within `near`, says something (then `delay` s later) or until
    `after` s have passed; then step aside to `to`. Without either the person stays."""
    state, now = person.step_state, world.t
    near = person._distance_to_robot(world) <= step.near
    said = len(world.utterances) - state.setdefault("heard", state["utterances"])
    state["heard"] = len(world.utterances)
    if "asked" not in state and step.asked and near and said > 0:
        state["asked"] = now
    going = (now - state.get("asked", math.inf) >= step.delay - 1e-9
             or now - person.step_started >= step.after - 1e-9)
    if not going:
        if near:
            person._face_robot(world)
        return False
    if "to" not in state:
        state["to"] = (person.resolve(step.to) if step.to is not None
                       else _aside(person, step, world))
    return person._walk_towards(*state["to"], dt)


def _aside(person: SimPerson, step: MakeWay, world: "World") -> tuple[float, float]:
    """`aside` m to the robot's left or right (of its heading now), shortened to stay clear of
    walls where that is possible."""
    sign = 1.0 if step.side == "left" else -1.0
    dx, dy = -math.sin(world.body.th) * sign, math.cos(world.body.th) * sign
    for share in (1.0, 0.75, 0.5, 0.25):
        target = (person.x + dx * step.aside * share, person.y + dy * step.aside * share)
        if world.walkable((person.x, person.y), target):
            return target
    return (person.x + dx * step.aside, person.y + dy * step.aside)


def _shop(person: SimPerson, step: Shop, dt: float, world: "World") -> bool:
    """Walk to each shelf place around the shelves and dwell there facing the shelf."""
    state, now = person.step_state, world.t
    if "places" not in state:
        state.update(places=list(step.places) or _draw_places(person, step, world), at=0,
                     dwell_until=None)
    places = state["places"]
    if state["at"] >= len(places):
        return True
    place = places[state["at"]]
    if state["dwell_until"] is None:
        if not _walk_routed(person, [place], dt, world, give_way=True):
            return False
        state.pop("target", None)
        person._face_place(place, world)
        low, high = step.dwell
        state["dwell_until"] = now + (low if high <= low else float(person.rng.uniform(low, high)))
    if now < state["dwell_until"] - 1e-9:
        return False
    state["at"] += 1
    state["dwell_until"] = None
    return state["at"] >= len(places)


def _draw_places(person: SimPerson, step: Shop, world: "World") -> list[str]:
    """`count` places with the prefix, never the same twice in a row, from the person's rng."""
    names = sorted(n for n in world.floor.places if n.startswith(step.prefix))
    drawn: list[str] = []
    for _ in range(step.count):
        choices = [n for n in names if not drawn or n != drawn[-1]] or names
        drawn.append(choices[int(person.rng.integers(len(choices)))])
    return drawn


def _lead(person: SimPerson, step: Lead, dt: float, world: "World") -> bool:
    """Walk the waypoints around walls at the person's pace, dwelling at each; wait while the
    robot is farther than `wait_beyond`; slow down or wait when it asks her to, as her heeding
    says (robots.sim.heeding)."""
    state, now = person.step_state, world.t
    if "dwell_until" not in state:
        if step.after_call and not person._called(world):
            person._face_robot(world)
            return False
        state["dwell_until"] = None
    if state["dwell_until"] is not None:
        if now < state["dwell_until"] - 1e-9:
            return False
        state["dwell_until"] = None
        if state["target"] >= len(step.waypoints):
            return True
    if person._distance_to_robot(world) > step.wait_beyond:
        person._face_robot(world)
        return False
    pace = _heeded_pace(person, state, world)
    if pace == 0.0:                   # asked to wait: stands for the robot
        person._face_robot(world)
        return False
    before = state.get("target", 0)
    done = _walk_routed(person, list(step.waypoints), dt, world, speed=pace)
    if state["target"] > before and step.dwell > 0:
        person._face_place(step.waypoints[before], world)
        state["dwell_until"] = now + step.dwell
        return False
    return done


def _heeded_pace(person: SimPerson, state: dict, world: "World") -> float | None:
    """Her pace as her heeding of the robot's asks says (robots.sim.heeding): None her own,
    0.0 standing for it. What it said before she began to lead is not said to her."""
    listener = person.heeding
    if listener is None:
        return None
    if "listening" not in state:
        state["listening"] = True
        listener.start(world)
    distance = person._distance_to_robot(world)
    return listener.pace(person, world, CALL_DISTANCE < distance <= visitors.HEAR)


def _sync(person: SimPerson, step: Sync, dt: float, world: "World") -> bool:
    """Stand until the other person has begun step `step` (or has gone for good)."""
    other = next(p for p in world.people if p.id == step.person)
    return other.gone or other.index >= step.step


_HANDLERS = {Walk: _walk, Pause: _pause, Approach: _approach, Answer: _answer,
             WaitForCall: _wait_for_call, Leave: _leave, Follow: _follow, MakeWay: _make_way,
             Shop: _shop, Lead: _lead, Sync: _sync}
_HANDLERS[visitors.Visit] = visitors.visit        # passers-by with propensities (issue 27)
