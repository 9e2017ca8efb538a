"""Letting the robot pass when it asks (issue 23): a shopper or passer-by in the robot's way
who hears it ask to pass steps aside, as people in a shop do, if they are one who yields to the
robot (their `yielding` trait, the one that decides whether they give way to it while walking,
`robots.sim.people`; drawn per person from the scenario's distribution, `robots.sim.crowd`).

**What counts as asking.** An utterance with words that ask to pass
(`robots.sim.understanding`: "excuse me", "pass", "make way", "let me through"), heard while
the person (or their cart) is in the robot's lane ahead of it within ASKED_NEAR m: a circle of
theirs nearer the line the robot faces than its radius, the circle's and LANE_MARGIN. Only
people standing about their own business listen for it (a `pause`, a shelf of `shop` they
dwell at, or giving way to the robot on a walk of `walk`, `leave` or `shop`; not people
walking, who pass anyway, nor whoever leads or follows the robot); a
scenario's `make_way` step still reacts to anything said, as before, and a customer leading
the robot does not take it for "wait for me" (`robots.sim.heeding`).

**Stepping aside.** After REACTION s, across the robot's heading to the side they already
stand on (its right when dead ahead), as far as clears the lane (at most ASIDE_MOST m), a
shorter step where a wall is in the way (none when not even a quarter of it is clear: they
have no room); a cart in the lane is first pulled in along it (turned, at a pushed cart's
turn rate, to the robot's heading or its opposite, whichever is nearer; not when the turn
would sweep it into the robot), then pushed aside with them. Without room to step aside and
without a cart to pull in, they go on as before. They stand aside until the robot has passed
(they are behind it along its heading by more than a cart's reach, SWING), is farther than
PASSED m, or PATIENCE s have
gone by, then go on with their step (a shopper at a shelf dwells on, a walker walks on);
arrived at their spot but still in its lane (pushed there, or the robot turned), they step
out of it again as it lies now, or go on at once where they have no room: standing there
helps nobody.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from robots.sim.scenario import Follow, Lead, Leave, Pause, Shop, Walk
from robots.sim.understanding import asks_to_pass

if TYPE_CHECKING:
    from robots.sim.people import SimPerson
    from robots.sim.world import World

ASKED_NEAR = 2.0        # m from the robot's centre to a circle of theirs: they are asked
LANE_MARGIN = 0.15      # m beside the robot's and their width that still counts as its lane
ASIDE_MOST = 0.9        # m at most stepped aside
REACTION = 1.0          # s between hearing the ask and stepping aside
PASSED = 3.0            # m: the robot this far off has gone elsewhere
SWING = 1.25            # m a cart reaches from its pusher's centre (people.CART_OFFSETS, radius)
PATIENCE = 6.0          # s they stand aside at most (as long as people give way, people.py)
CLEAR = 0.05            # m stepped beyond the lane's edge
MIN_SHARE = 0.25        # of the step aside that must be clear of walls, or they stay
HEARD_FOR = 1.0         # s: an ask said longer ago (before they came) is not heard now
SWEEP = (0.25, 0.5, 0.75, 1.0)   # shares of a cart's turn checked to keep clear of the robot


@dataclass
class Aside:
    """A person letting the robot pass: where to, the cart's heading pulled in along the
    robot's lane (None: as it is), from when they move, and when they were asked."""
    to: tuple[float, float]
    cart_heading: float | None
    go_at: float
    asked_at: float


def listen(person: "SimPerson", heard: list[tuple[float, str]], world: "World") -> None:
    """Begin letting the robot pass on an ask heard in its lane (see the module); the caller
    asks only of people who yield."""
    if person.aside is not None:
        return
    if not _standing_about_their_business(person):
        return
    if not any(asks_to_pass(text) and world.t - t <= HEARD_FOR for t, text in heard):
        return
    body = world.body
    if not _in_lane(person.circles(), body):
        return
    tuck = _tucked(person, body)
    circles = person.circles() if tuck is None else person.circles(cart_heading=tuck)
    shift = _out_of_lane(circles, body)
    spot = (person.x, person.y) if shift is None else _aside_spot(person, shift, world)
    if spot is None and tuck is not None:
        spot = (person.x, person.y)          # no room to step aside: the cart pulled in only
    if spot is not None:
        person.aside = Aside(spot, tuck, world.t + REACTION, world.t)


def carry_on(person: "SimPerson", dt: float, world: "World") -> bool:
    """Step aside or stand aside; False once done (the person's step goes on)."""
    aside = person.aside
    if aside is None:
        return False
    if _passed(person, world) or world.t - aside.asked_at >= PATIENCE - 1e-9:
        person.aside = None
        person.step_state.pop("path", None)      # a walk finds its way again from here
        return False
    if world.t >= aside.go_at - 1e-9:
        if aside.cart_heading is not None:
            person.turn_cart_to(aside.cart_heading, dt)
        there = person._walk_towards(*aside.to, dt) and (
            aside.cart_heading is None
            or abs(math.remainder(aside.cart_heading - person.cart_heading, math.tau)) < 1e-6)
        if there and _in_lane(person.circles(), world.body):
            return _step_further(person, world)
    return True


def _step_further(person: "SimPerson", world: "World") -> bool:
    """Arrived aside but in the robot's lane again (it turned, or they were pushed): out of
    its lane as it faces now, if there is room; else they go on (False), as standing there
    helps nobody. Going on, a stand-in who gives way stood 0.8 m ahead of a robot that had
    turned towards her after asking, and each waited for the other 7 s (bench_follow
    turnback seed 15, HOROS, issue 23)."""
    shift = _out_of_lane(person.circles(), world.body)
    spot = None if shift is None else _aside_spot(person, shift, world)
    if spot is None:
        person.aside = None
        return False
    person.aside = replace(person.aside, to=spot)
    return True


def _standing_about_their_business(person: "SimPerson") -> bool:
    """Standing in a step of their own: a pause, a shelf they dwell at, or giving way to the
    robot on a walk. Not someone walking (they are passing anyway: a crosser asked in a crowd
    stood aside for seconds, in the way of others), nor whoever leads or follows the robot
    (their pauses are the customer's, or the visitor's)."""
    step = person.current_step
    if any(isinstance(s, (Lead, Follow)) for s in person.steps):
        return False
    if isinstance(step, Pause):
        return True
    if isinstance(step, Shop) and person.step_state.get("dwell_until") is not None:
        return True
    return isinstance(step, (Walk, Leave, Shop)) and person.waiting_since is not None


def _lane(body, x: float, y: float, radius: float) -> tuple[float, float, float]:
    """A circle's place relative to the robot's lane: how far ahead, how far to its left
    (negative: right), and the half width of the lane for that circle."""
    hx, hy = math.cos(body.th), math.sin(body.th)
    rx, ry = x - body.x, y - body.y
    return rx * hx + ry * hy, hx * ry - hy * rx, body.radius + radius + LANE_MARGIN


def _across(body, x: float, y: float, radius: float) -> bool:
    """The circle lies across the line the robot faces (ahead of it or not)."""
    _, across, lane = _lane(body, x, y, radius)
    return abs(across) < lane


def _in_lane(circles, body) -> bool:
    """A circle in the robot's lane, ahead of it within ASKED_NEAR."""
    return any(_lane(body, x, y, r)[0] > 0.0 and _across(body, x, y, r)
               and math.hypot(x - body.x, y - body.y) <= ASKED_NEAR for x, y, r in circles)


def _tucked(person: "SimPerson", body) -> float | None:
    """The heading along the robot's lane (of its two ways, the nearer the cart's) to pull a
    cart in to when a circle of the cart is in the lane; None without one there."""
    if not any(_across(body, x, y, r) for x, y, r in person.cart_circles()):
        return None
    ahead = math.remainder(body.th - person.cart_heading, math.tau)
    tuck = body.th if abs(ahead) <= math.pi / 2 else body.th + math.pi
    turn = math.remainder(tuck - person.cart_heading, math.tau)
    for share in SWEEP:                        # the cart's sweep must keep clear of the robot
        for x, y, r in person.circles(cart_heading=person.cart_heading + share * turn)[1:]:
            if math.hypot(x - body.x, y - body.y) < body.radius + r + LANE_MARGIN:
                return None
    return tuck


def _out_of_lane(circles, body) -> tuple[float, float] | None:
    """The step (dx, dy) that takes every circle out of the robot's lane, to the side they are
    on (its right when dead ahead), at most ASIDE_MOST; None when none is in it."""
    need, side = 0.0, 0.0
    for x, y, radius in circles:
        _, across, lane = _lane(body, x, y, radius)
        side += across
        need = max(need, lane - abs(across))
    if need <= 0.0:
        return None
    sign = 1.0 if side > 0.0 else -1.0
    size = min(need + CLEAR, ASIDE_MOST)
    hx, hy = math.cos(body.th), math.sin(body.th)
    return -hy * sign * size, hx * sign * size


def _aside_spot(person: "SimPerson", shift: tuple[float, float], world: "World"
                ) -> tuple[float, float] | None:
    """The spot `shift` away, shortened to what they (and their cart) can walk clear of
    walls; None when not even MIN_SHARE of it is clear (they have no room to step aside, and
    go on with what they were doing)."""
    dx, dy = shift
    for share in (1.0, 0.75, 0.5, MIN_SHARE):
        if all(world.walkable((x, y), (x + dx * share, y + dy * share))
               for x, y, _ in person.circles()):
            return person.x + dx * share, person.y + dy * share
    return None


def _passed(person: "SimPerson", world: "World") -> bool:
    """The robot is past them by more than their cart's swing (a cart turned back to the
    walking heading beside a robot just past swung into its flank), or has gone elsewhere."""
    body = world.body
    along = _lane(body, person.x, person.y, 0.0)[0]
    return (along < -(body.radius + SWING)
            or math.hypot(person.x - body.x, person.y - body.y) > PASSED)

