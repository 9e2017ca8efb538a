"""Benchmark of FollowCustomer (skills/following/) over many seeded store scenarios.

Each seed makes a scenario on the store floor: the robot starts in the front aisle facing
east with the customer in front of it; she leads it east to a stop (the occlusion below), then
along one of four routes past three shelves, never back past the robot (simulated people do
not avoid the robot), at 0.4 .. 0.55 m/s with 3 .. 8 s at each shelf; two or three
other shoppers (some with carts) come in after 15 .. 60 s and visit random shelves; one more shopper waits for the
customer's stop in the front aisle and stands in the line of sight for an occlusion drawn from
1 .. 3 s. The robot (PERSES by default) follows from the start with the default parameters.
The other shoppers move by social forces and yield to the robot as their drawn trait says
(docs/scenarios.md, *How people move*); `--rude` makes none of them yield.
Against the simulator's ground truth it reports:

- the share of following time the distance (centre to centre) is within ±0.4 m of the 1.2 m
  setpoint, and within ±0.3 m (target ≥ 90 %); beside it, per family, the share a point
  robot with no obstacles and nobody in its way would keep within ±0.3 m driving straight
  along her true path within the profile's speed limits (`pursued_in_band`): what the
  limits allow when she walks faster than the robot (the fast families) or back at it;
  and the share the same pursuer keeps when also held to the near-people cap whenever anybody
  else is near it and not left behind: what the limits allow in a crowd;
- lost events (the follower enters `hidden`) per 10 minutes of following;
- re-acquisition: of the losses, the share found again within 5 s (target ≥ 90 % for
  occlusions up to 3 s), and the scripted occlusions' share;
- track misses: the share of frames the customer is in the detector's range and line of sight
  but the follower has no track of her (target ≤ 2.5 %); identity switches: times the
  followed track sat on someone else (nearer them and over 0.7 m from the customer) for a
  second, per 20 minutes (target ≤ 2);
- the minimum clearance (gap between outlines) to the other shoppers, and collisions (contacts
  with the robot moving; contacts of a person walking into a standing robot apart). A contact
  with the robot moving is further split by who closed in: the robot drove into the person (or
  cart) if it closed the gap between their outlines (HOROS's rectangle, not its centre) the
  faster, else the person walked into the robot while it turned or crept (simulated shoppers
  do not give way, docs/scenarios.md);
- the time the robot's own position estimate (localization) is 0.5 m or more off the truth,
  and the follower's reason when it gave up: a run given up with the robot's position lost
  ("localization lost, standing still") is localization's failure, not the search's.

Scenario families (`--family NAME`, repeatable, or `all`; issue 23): `base` (the shoppers'
yielding drawn per person), `polite` / `rude` (every other shopper yields fully / not at all),
`lookalike` (the stand-in is dressed exactly like her), `crowd5` / `crowd10` / `crowd20`
(that many more shoppers cross the front aisle around her stop), `turnback` (at the stop she
walks back at the robot), `standin2` / `standin5` / `standin8` (the stand-in stands that many
seconds), `fast` (she walks at 1.4 m/s), `fastwait` / `fastnever` (the same, and she
stops and waits when the robot asks her to / never heeds it), `carts` (every other shopper
pushes a cart). Per
family it prints the pooled share within ±0.3 m and the worst seed's, the time spent
following a track that is not hers, and losses counted from the moment her track is lost or
sits on somebody else (nearer them and over 0.7 m from her) until the followed track is hers
again; those losses split by how long she was out of the robot's view (beyond the detector's
range or behind a wall or someone) from the loss on: up to 5 s (target: ≥ 90 % found again
within 10 s) and longer.

Whether the customer heeds the robot when it asks her to wait (`skills.following.pace`) is
her trait (`robots.sim.heeding`), drawn per seed from the simulator's default distribution
(the scenarios state none): a quarter never heed, the others slow to 0.4 .. 0.55 m/s for
20 .. 60 s or stop and wait 3 .. 10 s, half each; she hears the robot within 7 m. Each seed's
line names her answer and how often the robot asked, said it lost her and she heard it; the
fast families print their figures apart for customers who heed and who never do.

    python benchmarks/bench_follow.py [--seeds N] [--first K] [--robot perses|horos] [--rude]
                                      [--family NAME ...] [--give-up S]

`--give-up` is the application's time unseen before the follower gives up (30 s, as the
shopping application sets it).

Prints the load average beside the figures: the machine is shared.
"""
from __future__ import annotations

import argparse
import math
import os
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from robots.sim.people import BODY_RADIUS
from robots.sim.raycast import cast_rays
from skills.following import HIDDEN, SEARCHING, pace
from skills.safety import LEFT_BEHIND
from skills.skillset import open_skills

SETPOINT = 1.2
POSE_OFF = 0.5      # m: the robot's own position estimate this far off the truth is wrong
SHORT_LOSS = 5.0    # s: a loss with her out of view no longer than this is a short one
ROUTES = [          # from the stop in the front aisle on, never back past the robot
    [["aisle4_south", "shelf_snacks"], ["aisle4_north", "aisle5_north", "shelf_petfood"],
     ["aisle5_south", [23.0, 5.5], "shelf_produce"]],
    [["aisle5_south", "shelf_household"], ["aisle5_north", "shelf_frozen"],
     [[20.0, 18.25], [23.0, 17.0], "shelf_produce"]],
    [["aisle4_south", "shelf_drinks"], ["aisle4_north", "aisle2_north", "shelf_dairy"],
     ["aisle1_north", "shelf_cereal"]],
    [[[23.0, 5.5], [23.0, 11.5], "shelf_produce"], [[25.5, 16.5], [20.0, 18.25], "shelf_frozen"],
     ["aisle5_north", "shelf_petfood"]],
]
STOP = [[12.5, 4.75]]      # the customer's walk along the front aisle, then a stop


def point(p) -> str:
    return f'"{p}"' if isinstance(p, str) else f"[{p[0]}, {p[1]}]"


FAMILIES = {      # name: what differs from the base scenario (see the module's docstring)
    "base": {}, "polite": {"yielding": 1.0}, "rude": {"yielding": 0.0},
    "lookalike": {"look_alike": True}, "crowd5": {"crowd": 5}, "crowd10": {"crowd": 10},
    "crowd20": {"crowd": 20}, "turnback": {"turn_back": True}, "standin2": {"occlusion": 2.0},
    "standin5": {"occlusion": 5.0}, "standin8": {"occlusion": 8.0}, "fast": {"speed": 1.4},
    "fastwait": {"speed": 1.4, "heeding": "wait"}, "fastnever": {"speed": 1.4, "heeding": "never"},
    "carts": {"carts": True},
}


def scenario(seed: int, give_way: bool | None = True, family: str = "base"
             ) -> tuple[str, float]:
    """The scenario text for `seed` (of `family`) and its scripted occlusion (s)."""
    rng = np.random.default_rng(seed)
    spec = FAMILIES[family]
    route = ROUTES[seed % len(ROUTES)]
    speed = round(float(rng.uniform(0.4, 0.55)), 2)
    occlusion = round(float(rng.uniform(1.0, 3.0)), 1)
    speed = spec.get("speed", speed)
    occlusion = spec.get("occlusion", occlusion)
    legs = [f"{{ lead = [{', '.join(point(p) for p in STOP)}] }}", "{ pause = 10.0 }"]
    if spec.get("turn_back"):
        legs[1] = "{ pause = 4.0 }, { approach = 0.3 }, { pause = 4.0 }"
    for leg in route:
        legs.append(f"{{ lead = [{', '.join(point(p) for p in leg)}] }}")
        legs.append(f"{{ pause = {rng.uniform(3.0, 8.0):.1f} }}")
    legs[-1] = "{ pause = 20.0 }"
    text = f"""[scenario]
name = "bench_follow_{seed}"
duration = 200.0
robot = [6.5, 3.5, 0.0]
floor = "store"

[[person]]
id = "customer"
appear = 0.0
at = [7.8, 3.7]
speed = {speed}
{f'heeding = "{spec["heeding"]}"' if "heeding" in spec else ""}
steps = [ {{ pause = 4.0 }}, {', '.join(legs)} ]

[[person]]
id = "occluder"
at = [12.1, 1.6]
speed = 1.0
{'looks_like = "customer"' if spec.get("look_alike") else ""}
{"cart = true" if spec.get("carts") else ""}
steps = [ {{ sync = "customer", step = 2 }}, {{ pause = 3.0 }}, {{ walk = [[12.1, 4.75]] }},
          {{ pause = {occlusion} }}, {{ walk = [[12.1, 5.5], [14.0, 5.5], "aisle4_south"]  }},
          {{ shop = "shelf_", count = 3, dwell = [4.0, 8.0] }} ]
"""
    yielding = spec.get("yielding", None if give_way is None else float(give_way))
    trait = "" if yielding is None else f"yielding = {yielding}"
    for k in range(int(rng.integers(2, 4))):
        cart = "true" if spec.get("carts") or rng.random() < 0.5 else "false"
        text += f"""
[[person]]
id = "shopper{k}"
appear = {rng.uniform(15.0, 60.0):.1f}
at = "entrance"
speed = {rng.uniform(0.6, 1.0):.2f}
cart = {cart}
{trait}
steps = [ {{ shop = "shelf_", count = 4, dwell = [3.0, 10.0] }}, {{ leave = "street", route = true }} ]
"""
    for k in range(spec.get("crowd", 0)):      # shoppers crossing the front aisle at her stop
        x = rng.uniform(9.5, 15.5)
        south, north = [round(x, 2), 3.4], [round(x + rng.uniform(-1.0, 1.0), 2), 6.2]
        start, end = (south, north) if rng.random() < 0.5 else (north, south)
        text += f"""
[[person]]
id = "crosser{k}"
at = [{start[0]}, {start[1]}]
speed = {rng.uniform(0.7, 1.3):.2f}
cart = {"true" if rng.random() < 0.2 else "false"}
{trait}
steps = [ {{ sync = "customer", step = 2 }}, {{ pause = {rng.uniform(0.0, 12.0):.1f} }},
          {{ walk = [[{end[0]}, {end[1]}]] }}, {{ leave = "street", route = true }} ]
"""
    return text, occlusion


@dataclass
class Result:
    ticks: int = 0                  # ticks following
    in_band: int = 0
    in_tight_band: int = 0
    losses: list = field(default_factory=list)      # (start, duration or None)
    occlusion_found: bool | None = None
    visible: int = 0                # frames the customer was in range and line of sight
    missed: int = 0                 # ... of those without a track of her
    switches: int = 0
    clearance_others: float = math.inf
    collisions: int = 0
    drove_into: int = 0             # ... of the collisions, those the robot closed in on
    walked_into: int = 0
    gave_up: bool = False
    episodes: list = field(default_factory=list)    # [start, duration or None, out of view or
                                                    # None]: her track lost or on somebody
                                                    # else, until back on her; and how long she
                                                    # was out of the robot's view from the start
    wrong_ticks: int = 0            # ticks following a track that is not hers
    pose_off: int = 0               # ticks the localization estimate is POSE_OFF m or more off
    pose_errors: list = field(default_factory=list)   # m: the estimate's position error, per tick
    reason: str = ""                # the follower's reason when it gave up
    heed: str = ""                  # how the customer answers "wait for me" (robots.sim.heeding)
    asked: int = 0                  # times the robot asked her to wait (pace.ASK) ...
    said_lost: int = 0              # ... said it lost her (pace.LOST) ...
    heard: int = 0                  # ... and she heard something it said, leading it
    path: list = field(default_factory=list)        # (t, x, y): where she was, every tick
                                                    # following, and where the robot began
    start: tuple = (0.0, 0.0)
    reference_band: int = 0         # ticks an unobstructed pursuer is within ±0.3 m (below)
    others: list = field(default_factory=list)      # ((x, y), ...) of everybody else, per
                                                    # entry of `path`
    reference_capped: int = 0       # the same pursuer also slowed near everybody else


def line_of_sight(world, a, b, people, customer) -> bool:
    """Nothing between a and b: no wall or shelf side crossing the line, and nobody's body
    but the customer's within BODY_RADIUS of it (the camera's rule, `World.person_detections`;
    carts are lower than the camera). Sampling nine points of the line against the walls'
    outlines let it pass through a shelf, whose inside is no outline: 'in view' counted her
    behind a shelf (PERSES crowd10 seed 0, 8 s of such misses)."""
    d = math.hypot(b[0] - a[0], b[1] - a[1])
    if d < 1e-9:
        return True
    angle = np.array([math.atan2(b[1] - a[1], b[0] - a[0])])
    origin = np.array([[a[0], a[1]]])
    if cast_rays(origin, angle, np.asarray(world._walls), None, d)[0] < d:
        return False
    others = np.array([(p.x, p.y, BODY_RADIUS) for p in people if p is not customer]
                      ).reshape(-1, 3)
    return not len(others) or cast_rays(origin, angle, None, others, d)[0] >= d


def _circles(person) -> list:
    """A person's outline as circle centres: their body, then their cart's (if any)."""
    return [(person.x, person.y)] + [(x, y) for x, y, _ in person.cart_circles()]


def _positions(world) -> dict:
    """Where the robot (its pose) and each person (body and cart circles) stand now (for
    velocities over the next tick)."""
    where = {p.plan.id: _circles(p) for p in world.present_people()}
    where["robot"] = (world.body.x, world.body.y, world.body.th)
    return where


def _gap(body, pose, centre, radius: float) -> float:
    """Gap between the robot's outline at `pose` and a circle (its rectangle for a box-shaped
    robot, HOROS; its bounding circle for a round one)."""
    return body.gap_to_circles(np.array([(*centre, radius)]), *pose)


def _robot_closed_in(contact, world, before: dict, dt: float = 0.1) -> bool:
    """Whether the robot closed the gap to the thing it touched (the person, or their cart)
    faster than that thing closed it, over the tick the contact began in. Gaps are between
    outlines (`_gap`): a box-shaped robot driving along a cart pressed to its side does not
    close in on it, though its centre nears the cart's (HOROS rude seed 2, issue 23), and its
    corner sweeping round into someone does, though its centre stays put. For a round robot
    this is the centres' approach. A cart's speed is its circle's, so a cart the person swings
    round into the robot (the simulated cart turns with the walker at once) is theirs: the
    person's centre barely moves (crowd20 seed 1, issue 23: two such swings were counted as
    driven into). The thing is the part the simulator found touching (`contact.part`), not the
    part nearest at the tick's end: the crowd pushes a person off the robot within the tick,
    which can leave another part nearer (HOROS crowd20 seed 19, issue 23: a cart swung into
    the robot's side from behind was judged by its far circle, which the creeping robot
    neared)."""
    person = next((p for p in world.present_people() if p.plan.id == contact.who), None)
    if person is None or "robot" not in before or contact.who not in before:
        return True                          # cannot tell: count it against the robot
    body = world.body
    pose, was_at = (body.x, body.y, body.th), before["robot"]
    circles = _circles(person)
    radii = [BODY_RADIUS] + [r for _, _, r in person.cart_circles()]
    k = contact.part if contact.part < len(circles) else 0
    earlier = before[contact.who]
    then = earlier[k] if k < len(earlier) else earlier[0]
    # the gap's change over the tick, split into the thing's part (seen from where the robot
    # was) and the robot's (towards where the thing is now); a swinging cart is not a
    # straight-line motion, so the gap is compared, not a velocity along one line
    robot_closing = (_gap(body, was_at, circles[k], radii[k])
                     - _gap(body, pose, circles[k], radii[k])) / dt
    person_closing = (_gap(body, was_at, then, radii[k])
                      - _gap(body, was_at, circles[k], radii[k])) / dt
    return robot_closing > 0.02 and robot_closing >= person_closing


def run(seed: int, robot: str, folder: Path, give_way: bool | None = True,
        family: str = "base", give_up: float = 30.0) -> Result:
    text, occlusion = scenario(seed, give_way, family)
    path = folder / f"bench_follow_{seed}.toml"
    path.write_text(text, encoding="utf-8")
    skills = open_skills(robot, scenario=path, fast=True, seed=seed)
    result = Result()
    try:
        clock, world = skills.hardware.clock, skills.hardware.simulation.world
        following = skills.following
        detector = skills.profile.people_detector
        reach = detector.range if detector is not None else 5.0
        started, previous, lost_at, wrong_for = None, "idle", None, 0
        occlusion_start = None
        before, contacts_seen = {}, 0
        for _ in range(int(world.scenario.duration * 10)):
            now = skills.sense()
            people = list(world.present_people())
            customer = next((p for p in people if p.plan.id == "customer"), None)
            body = world.body
            if started is None and skills.perception.user is not None and now >= 1.0:
                following.follow(now, give_up_after=give_up)
                started = now
                result.start = (body.x, body.y)
            skills.act()
            clock.advance(0.1)
            contacts = world.measures.contacts
            for contact in contacts[contacts_seen:]:
                if contact.robot_moving and _robot_closed_in(contact, world, before):
                    result.drove_into += 1
            contacts_seen = len(contacts)
            before = _positions(world)
            if started is None or customer is None:
                continue
            state = following.state
            pose = skills.localization.state
            error = math.inf if pose is None else math.hypot(pose.x - body.x, pose.y - body.y)
            result.pose_errors.append(error)
            result.pose_off += error >= POSE_OFF
            if state.phase == "gave_up":
                result.gave_up, result.reason = True, state.reason
                break
            result.path.append((now - started, customer.x, customer.y))
            result.others.append(tuple((p.x, p.y) for p in people if p is not customer))
            if now - started >= 5.0:
                result.ticks += 1
                d = math.hypot(customer.x - body.x, customer.y - body.y)
                result.in_band += abs(d - SETPOINT) <= 0.4
                result.in_tight_band += abs(d - SETPOINT) <= 0.3
            lost = state.phase in (HIDDEN, SEARCHING)
            if lost and previous not in (HIDDEN, SEARCHING):
                lost_at = now
                result.losses.append([now, None])
            if not lost and previous in (HIDDEN, SEARCHING) and lost_at is not None:
                result.losses[-1][1] = now - lost_at
            previous = state.phase
            occluder = next((p for p in people if p.plan.id == "occluder"), None)
            if occlusion_start is None and occluder is not None and occluder.index >= 3:
                occlusion_start = now
            if (occlusion_start is not None and result.occlusion_found is None
                    and now - occlusion_start > occlusion + 5.0):
                result.occlusion_found = all(duration is not None and
                                             start + duration <= occlusion_start + occlusion + 5.0
                                             for start, duration in result.losses
                                             if start >= occlusion_start - 0.5)
            d = math.hypot(customer.x - body.x, customer.y - body.y)
            in_view = d <= reach and line_of_sight(world, (body.x, body.y),
                                                   (customer.x, customer.y), people, customer)
            if in_view:
                result.visible += 1
                result.missed += lost
            on_her = False
            if not lost:
                track = next((t for t in skills.perception.believed if t.id == state.target),
                             None)
                if track is not None:
                    on_her = on_the_customer(track, people, customer)
                    result.wrong_ticks += not on_her
                    # a switch: the followed track sits on somebody else for a second; counted
                    # once per episode
                    wrong_for = 0 if on_her else wrong_for + 1
                    if wrong_for == 10:
                        result.switches += 1
            if not on_her and (not result.episodes or result.episodes[-1][1] is not None):
                result.episodes.append([now, None, None])
            episode = result.episodes[-1] if result.episodes else None
            if episode is not None and episode[1] is None:
                if in_view and episode[2] is None:
                    episode[2] = now - episode[0]
                if on_her:
                    episode[1] = now - episode[0]
                    if episode[2] is None:
                        episode[2] = episode[1]
        _heeding(result, world)
        result.reference_band = pursued_in_band(result.path, result.start,
                                                skills.profile.limits)
        result.reference_capped = pursued_in_band(result.path, result.start,
                                                  skills.profile.limits, result.others)
        measures = world.measures
        result.clearance_others = min((gap for who, gap in measures.min_person_clearance.items()
                                       if who != "customer"), default=math.inf)
        result.collisions = sum(1 for c in measures.contacts if c.robot_moving)
        result.walked_into = sum(1 for c in measures.contacts if not c.robot_moving)
        return result
    finally:
        skills.close()


def on_the_customer(track, people, customer) -> bool:
    """The benchmark's rule for a followed track: it is hers unless it sits on somebody else,
    nearer them than her and over 0.7 m from her."""
    nearest = min(people, key=lambda p: math.hypot(p.x - track.x, p.y - track.y))
    return nearest is customer or math.hypot(customer.x - track.x, customer.y - track.y) <= 0.7


def pursued_in_band(path: list, start: tuple, limits, others: list | None = None,
                    dt: float = 0.1) -> int:
    """Ticks (from 5 s on, as the robot's share counts them) that a point robot with no
    obstacles, nobody in its way and no delay or acceleration, driving straight towards or away
    from her to keep SETPOINT within the profile's speed limits, is within ±0.3 m of it along
    her true path. Its top speed is `max_speed` while she recedes from it, else
    `max_speed_near_people` within `near_people_distance` (the safety arbiter's cap, which the
    follower lifts only for a receding customer). With `others` (per entry of `path`, where
    everybody else stands) the cap also holds whenever one of them is that near and not left
    behind (within LEFT_BEHIND of the way it drives), as the arbiter's is: what the limits
    allow in a crowd. A reference for what the limits allow, not a bound: shelves and people
    in the way only make it harder, and a pursuer that knew her path in advance could do a
    little better."""
    x, y = start
    inside, before = 0, None
    for k, (t, hx, hy) in enumerate(path):
        gap = math.hypot(hx - x, hy - y)
        receding = before is not None and gap > math.hypot(before[0] - x, before[1] - y)
        top = (limits.max_speed if receding or gap >= limits.near_people_distance
               else limits.max_speed_near_people)
        if others is not None and gap > 1e-9 and _near_ahead(
                others[k], (x, y), math.atan2(hy - y, hx - x) + (gap < SETPOINT) * math.pi,
                limits.near_people_distance):
            top = min(top, limits.max_speed_near_people)
        if gap > 1e-9:
            move = max(-top * dt, min(top * dt, gap - SETPOINT))
            x, y = x + (hx - x) / gap * move, y + (hy - y) / gap * move
        if t >= 5.0:
            inside += abs(math.hypot(hx - x, hy - y) - SETPOINT) <= 0.3
        before = (hx, hy)
    return inside


def _near_ahead(people, at: tuple, way: float, distance: float) -> bool:
    """Somebody within `distance` of `at` and not left behind by driving along `way` (rad)."""
    return any(math.hypot(px - at[0], py - at[1]) < distance
               and abs(math.remainder(math.atan2(py - at[1], px - at[0]) - way, math.tau))
               <= LEFT_BEHIND for px, py in people)


def _heeding(result: Result, world) -> None:
    """How the customer answers the robot's asks, and how often it asked and she heard."""
    customer = next(p for p in world.people if p.plan.id == "customer")
    heed = customer.heeding.heed
    result.heed = {"never": "never", "slow": f"slow ({heed.pace:.2f} m/s for "
                   f"{heed.slow_for:.0f} s)", "wait": f"wait ({heed.patience:.1f} s)"}[heed.how]
    result.asked = sum(text == pace.ASK for _, text in world.utterances)
    result.said_lost = sum(text == pace.LOST for _, text in world.utterances)
    result.heard = customer.heeding.heard


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--first", type=int, default=0, help="the first seed (then --seeds)")
    parser.add_argument("--robot", default="perses")
    parser.add_argument("--rude", action="store_true",
                        help="the base family's other shoppers do not give way to the robot")
    parser.add_argument("--family", action="append", choices=[*FAMILIES, "all"],
                        help="scenario families to run (repeat; default: base)")
    parser.add_argument("--give-up", type=float, default=30.0,
                        help="s unseen before the follower gives up (the application's "
                             "give_up_after; the shopping application's 30 s by default)")
    options = parser.parse_args()
    families = options.family or ["base"]
    if "all" in families:
        families = list(FAMILIES)
    print(f"{options.robot}, {options.seeds} seed(s) from {options.first} per family, giving "
          f"up after {options.give_up:g} s unseen")
    from machine import numpy_kernels    # this script's folder: per-seed lines are exact
    print(numpy_kernels())               # between machines whose line here is the same
    for family in families:
        start = time.perf_counter()
        results = []
        with tempfile.TemporaryDirectory() as folder:
            for seed in range(options.first, options.first + options.seeds):
                give_way = False if options.rude else None       # None: drawn per person
                r = run(seed, options.robot, Path(folder), give_way=give_way, family=family,
                        give_up=options.give_up)
                results.append(r)
                print_seed(family, seed, r)
        print_family(family, results, time.perf_counter() - start)


def print_seed(family: str, seed: int, r: Result) -> None:
    print(f"{family} seed {seed:2d}: {r.ticks / 10:.0f} s following, "
          f"±0.4 m {r.in_band / max(r.ticks, 1):6.1%} "
          f"(±0.3 m {r.in_tight_band / max(r.ticks, 1):6.1%}), losses "
          f"{[(round(s, 1), None if d is None else round(d, 1)) for s, d, _ in r.episodes]}, "
          f"wrong person {r.wrong_ticks / 10:.1f} s, misses {r.missed}/{r.visible}, clearance "
          f"to others {r.clearance_others:.2f} m, collisions {r.collisions} (robot drove in "
          f"{r.drove_into}) (walked into {r.walked_into}), own position off by "
          f"{POSE_OFF} m or more {r.pose_off / 10:.1f} s ({pose_summary(r.pose_errors)}); "
          f"she heeds: {r.heed}, asked to wait {r.asked}, said lost {r.said_lost}, heard "
          f"{r.heard}"
          f"{', GAVE UP: ' + r.reason if r.gave_up else ''}",
          flush=True)


def split_losses(results: list) -> tuple[tuple[int, int], tuple[int, int]]:
    """(losses, found again within 10 s) of the losses she was out of the robot's view for up
    to SHORT_LOSS s (in range and line of sight again within it; in view all along counts as
    0 s), and (losses, found again at all) of the rest, a run's end with her still out of view
    among them (issue 23: "losses of up to 5 s found again within 10 s in ≥ 90 %")."""
    short, longer = [0, 0], [0, 0]
    for r in results:
        for _, duration, out in r.episodes:
            if out is not None and out <= SHORT_LOSS:
                short[0] += 1
                short[1] += duration is not None and duration <= 10.0
            else:
                longer[0] += 1
                longer[1] += duration is not None
    return tuple(short), tuple(longer)


def pose_summary(errors: list) -> str:
    """The localization error over a run (or pooled runs): median, 95th percentile, maximum and
    the share of ticks within 0.3 m of the truth."""
    if not errors:
        return "no pose error measured"
    e = np.asarray(errors, dtype=float)
    return (f"pose error median {np.median(e):.3f} m, p95 {np.percentile(e, 95):.2f} m, "
            f"max {e.max():.2f} m, within 0.3 m {np.mean(e <= 0.3):.1%}")


def print_family(family: str, results: list, wall: float) -> None:
    """Pooled figures and the worst seed of one family."""
    ticks = max(sum(r.ticks for r in results), 1)
    minutes = ticks / 600.0
    shares = [r.in_tight_band / max(r.ticks, 1) for r in results]
    episodes = [d for r in results for _, d, _ in r.episodes]
    found = sum(1 for d in episodes if d is not None and d <= 10.0)
    short, longer = split_losses(results)
    print(f"== {family}: {len(results)} seed(s), {minutes:.1f} min of following ({wall:.0f} s "
          f"wall), load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    low, high = seed_interval([r.in_tight_band for r in results], [r.ticks for r in results])
    print(f"   within ±0.3 m: pooled {sum(r.in_tight_band for r in results) / ticks:.1%}, worst "
          f"seed {min(shares):.1%}   (targets ≥ 90 % pooled, ≥ 80 % every seed); pooled over "
          f"seeds drawn again: 90 % of draws within {low:.1%} .. {high:.1%}")
    reference = [r.reference_band / max(r.ticks, 1) for r in results]
    print(f"   an unobstructed pursuer within the robot's speed limits along her path (the "
          f"reference of `pursued_in_band`): pooled {sum(r.reference_band for r in results) / ticks:.1%}, "
          f"worst seed {min(reference):.1%}")
    capped = [r.reference_capped / max(r.ticks, 1) for r in results]
    print(f"   the same pursuer also held to max_speed_near_people near everybody else (the "
          f"arbiter's cap): pooled {sum(r.reference_capped for r in results) / ticks:.1%}, "
          f"worst seed {min(capped):.1%}")
    print(f"   following the wrong person: {sum(r.wrong_ticks for r in results) / 10:.1f} s "
          f"(target 0); losses (track lost or on someone else): {len(episodes)}, found again "
          f"within 10 s: {found}/{len(episodes)}")
    print(f"   losses with her out of view up to {SHORT_LOSS:g} s: {short[0]}, found again within "
          f"10 s: {short[1]}/{short[0]} (target ≥ 90 %); out of view longer: {longer[0]}, "
          f"found again: {longer[1]}/{longer[0]}")
    print(f"   contacts the robot drove into: {sum(r.drove_into for r in results)} (target 0); "
          f"people walking into it: {sum(r.walked_into for r in results)}; min clearance to "
          f"others {min(r.clearance_others for r in results):.2f} m; gave up: "
          f"{sum(r.gave_up for r in results)}/{len(results)}", flush=True)
    lost_pose = sum(r.gave_up and "localization" in r.reason for r in results)
    print(f"   the robot's own position off by {POSE_OFF} m or more: "
          f"{sum(r.pose_off for r in results) / 10:.1f} s; of the runs given up, "
          f"{lost_pose} with its position lost (localization), so it could not search",
          flush=True)
    if "speed" in FAMILIES[family]:
        print_heeding(results)
    pooled = [e for r in results for e in r.pose_errors]
    worst = min(results, key=lambda r: np.mean(np.asarray(r.pose_errors) <= 0.3)
                if r.pose_errors else 1.0)
    print(f"   localization: pooled {pose_summary(pooled)}; worst seed "
          f"{pose_summary(worst.pose_errors)}", flush=True)


def seed_interval(inside: list, ticks: list, draws: int = 2000) -> tuple[float, float]:
    """The 5th and 95th percentiles of the pooled share over the seeds drawn again with
    replacement (a bootstrap): how far the pooled figure moves with the seeds alone, so a
    difference between two commits smaller than that is not told from chance."""
    inside, ticks = np.asarray(inside, float), np.maximum(np.asarray(ticks, float), 1.0)
    pick = np.random.default_rng(0).integers(0, len(inside), (draws, len(inside)))
    pooled = inside[pick].sum(axis=1) / ticks[pick].sum(axis=1)
    return float(np.percentile(pooled, 5)), float(np.percentile(pooled, 95))


def print_heeding(results: list) -> None:
    """The fast families' figures apart for customers who heed the robot and who never do."""
    for label, group in (("heeding", [r for r in results if not r.heed.startswith("never")]),
                         ("never heeding", [r for r in results if r.heed.startswith("never")])):
        if not group:
            print(f"   customers {label}: none among these seeds")
            continue
        ticks = max(sum(r.ticks for r in group), 1)
        short, _ = split_losses(group)
        print(f"   customers {label} ({len(group)}): within ±0.3 m pooled "
              f"{sum(r.in_tight_band for r in group) / ticks:.1%}, worst seed "
              f"{min(r.in_tight_band / max(r.ticks, 1) for r in group):.1%}; gave up "
              f"{sum(r.gave_up for r in group)}/{len(group)}; losses out of view up to "
              f"{SHORT_LOSS:g} s found within 10 s {short[1]}/{short[0]}; asked "
              f"{sum(r.asked for r in group)}, said lost {sum(r.said_lost for r in group)}",
              flush=True)


if __name__ == "__main__":
    main()
