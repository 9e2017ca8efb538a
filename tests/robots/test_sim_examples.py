"""The example scenarios of `robots/sim/examples/` load on their floors and their people do
what the files say, played against stand-ins for the guide and for a following robot (the real
behaviors live in upper layers, which L0 tests must not import)."""
import math
from dataclasses import replace
from pathlib import Path

import pytest

from robots.clock import SimClock
from robots.profile import load_profile
from robots.sim.people import BODY_RADIUS
from robots.sim.raycast import point_segment_distances
from robots.sim.scenario import Follow, load_scenario
from robots.sim.simulation import Simulation

from sim_driver import Driver

EXAMPLES = Path(__file__).resolve().parents[2] / "robots/sim/examples"
OFFICE_EXAMPLES = ["office_follow", "office_stop_halfway", "office_walk_away",
                   "office_group_blocking"]
STORE_EXAMPLES = ["store_lead", "store_occlusion", "store_shoppers", "store_walk_off"]


def simulation(name, robot="horos", seed=0):
    return Simulation(load_profile(robot), EXAMPLES / f"{name}.toml", seed, SimClock())


def test_every_example_loads_on_its_own_floor():
    present = sorted(p.stem for p in EXAMPLES.glob("*.toml"))
    assert present == sorted(OFFICE_EXAMPLES + STORE_EXAMPLES)
    for name in present:
        sim = simulation(name)
        assert sim.scenario.name == name and sim.scenario.description
        assert sim.world.floor.name == name.split("_")[0]


# -- the office: a stand-in guide -----------------------------------------------------------

ROUTES = {"room_n2": [(0.0, 0.0), (-2.5, 0.0), (-2.5, 1.2), (-2.5, 3.2)],
          "room_n1": [(0.0, 0.0), (-7.5, 0.0), (-7.5, 1.2), (-7.5, 3.2)]}


def in_the_way(world, person):
    """The person stands less than 1.2 m ahead of the robot and less than 0.6 m aside."""
    body = world.body
    dx, dy = person.x - body.x, person.y - body.y
    ahead = dx * math.cos(body.th) + dy * math.sin(body.th)
    aside = -dx * math.sin(body.th) + dy * math.cos(body.th)
    return 0.0 < ahead < 1.2 and abs(aside) < 0.6


def guide(name, limit=150.0):
    """Show the destination prompt, ask the visitor to follow, drive the route, wait when they
    fall behind, ask a group to let it pass; returns what happened."""
    sim = simulation(name)
    world = sim.world
    visitor = world.people[-1]
    follow = next(s for s in visitor.plan.steps if isinstance(s, Follow))
    goal = follow.goal or "room_n2"
    log = {"waited": 0.0, "asked_to_pass": 0, "visitor": visitor, "world": world}
    driver = None
    while world.t < limit:
        world.step(0.1)
        if driver is None:
            if visitor.index == 2:                     # the answer step: show the question
                world.screen.show("where", "Where to?", ("Room N1", "Room N2"), world.t)
            if world.screen.take_press():
                world.screen.clear()
                world.say("Please follow me")
                driver = Driver(world, ROUTES[goal], speed=0.5)
            continue
        behind = math.hypot(visitor.x - world.body.x, visitor.y - world.body.y)
        blocking = [p for p in world.present_people() if p is not visitor and in_the_way(world, p)]
        driver.paused = (visitor.in_world and behind > 3.0) or bool(blocking)
        if visitor.in_world and behind > 3.0:
            log["waited"] += 0.1
        if blocking and log["asked_to_pass"] == 0:
            world.say("Excuse me, may I pass?")
            log["asked_to_pass"] += 1
        if driver.arrived and (visitor.current_step is None or visitor.gone):
            break
        if not visitor.in_world and driver.arrived:
            break
    log["arrived"] = driver is not None and driver.arrived
    return log


def test_office_follow_the_visitor_follows_into_the_room():
    log = guide("office_follow")
    visitor, world = log["visitor"], log["world"]
    assert log["arrived"] and log["waited"] == 0.0
    assert visitor.current_step is None                # followed, then took a seat
    assert (visitor.x, visitor.y) == pytest.approx((-4.0, 2.2), abs=0.03)
    assert visitor.pressed[0][2] == "Room N2"
    assert world.measures.contact_count() == 0


def test_office_stop_halfway_the_guide_waits_and_the_visitor_comes_on():
    log = guide("office_stop_halfway")
    assert log["arrived"] and 3.0 < log["waited"] < 12.0   # stood 10 s; robot waited
    assert log["visitor"].current_step is None and log["visitor"].y > 1.2


def test_office_walk_away_the_visitor_leaves_for_good():
    log = guide("office_walk_away")
    visitor = log["visitor"]
    assert visitor.gone and (visitor.x, visitor.y) == pytest.approx((9.5, 0.0), abs=0.03)


def test_office_group_blocking_makes_way_when_asked():
    log = guide("office_group_blocking", limit=180.0)
    world = log["world"]
    assert log["asked_to_pass"] == 1 and log["arrived"]
    assert log["visitor"].current_step is None and log["visitor"].y > 1.2
    assert world.measures.contact_count() == 0
    group = [p for p in world.people if p.id in ("gina", "gus", "greta")]
    assert all(abs(p.y) >= 0.92 for p in group)        # they stepped aside


# -- the store: an ideal follower ------------------------------------------------------------

def follow_ideally(world, person, distance=1.2):
    """Place the robot `distance` behind the person along the way they walked."""
    history = world.__dict__.setdefault("_walked", [(person.x, person.y)])
    if math.dist(history[-1], (person.x, person.y)) > 0.05:
        history.append((person.x, person.y))
    left, (x, y) = distance, history[-1]
    for px, py in reversed(history[:-1]):
        step = math.dist((x, y), (px, py))
        if step >= left:
            x, y = x + (px - x) * left / step, y + (py - y) * left / step
            break
        left -= step
        x, y = px, py
    world.body.x, world.body.y = x, y
    world.body.th = math.atan2(person.y - y, person.x - x) if (x, y) != (person.x,
                                                                        person.y) else 0.0


def play_store(name, robot="perses", limit=240.0):
    """Answer the customer's prompt, say "I follow you", then follow her ideally."""
    sim = simulation(name, robot)
    world = sim.world
    customer = world.people[0]
    following, walls = False, []
    while world.t < limit and not (following and customer.current_step is None):
        world.step(0.1)
        if not following:
            if customer.index == 2:
                world.screen.show("what", "How can I help?", ("Find a product", "Follow me"),
                                  world.t)
            if world.screen.take_press():
                world.say("I will follow you")
                following = True
        else:
            follow_ideally(world, customer)
        for person in world.present_people():
            walls.append(float(point_segment_distances(person.x, person.y,
                                                       world.floor.segments).min()))
        yield world, customer
    assert min(walls) >= BODY_RADIUS


def test_store_lead_the_customer_leads_through_three_aisles_to_the_checkout():
    visited = set()
    for world, customer in play_store("store_lead"):
        for name in ("shelf_bakery", "shelf_pasta", "shelf_snacks", "aisle1_north",
                     "aisle2_south", "aisle4_south"):
            if math.dist((customer.x, customer.y), world.floor.places[name][:2]) < 0.05:
                visited.add(name)
    assert len(visited) == 6
    assert (customer.x, customer.y) == pytest.approx(world.floor.places["checkout"][:2],
                                                     abs=0.03)


def test_store_occlusion_the_shopper_hides_the_customer_for_about_two_seconds():
    exact = load_profile("perses")
    camera_hidden = laser_hidden = 0.0
    for world, customer in play_store("store_occlusion"):
        if world.people[0].index != 4:                 # only while she stands and waits
            continue
        world.profile = replace(exact, laser=replace(exact.laser, noise=0.0),
                                people_detector=replace(exact.people_detector, noise=0.0,
                                                        miss_rate=0.0, false_rate=0.0))
        distance = math.hypot(customer.x - world.body.x, customer.y - world.body.y)
        if not any(abs(math.hypot(x, y) - distance) < 0.1 for x, y in world.detect_people()):
            camera_hidden += 0.1
        angles, ranges = world.laser_scan()
        bearing = math.atan2(customer.y - world.body.y, customer.x - world.body.x) - world.body.th
        near = (abs(angles - bearing) < 0.15) & (abs(ranges - distance) < 0.3)
        if not near.any():
            laser_hidden += 0.1
    assert 1.7 <= camera_hidden <= 2.4                 # his body, 1.6 s standing and passing
    assert 2.2 <= laser_hidden <= 3.2                  # his cart ahead of him, then his legs


def test_store_walk_off_the_customer_leaves_the_store_after_one_shelf():
    reached_coffee = False
    for world, customer in play_store("store_walk_off"):
        coffee = world.floor.places["shelf_coffee"][:2]
        reached_coffee |= math.dist((customer.x, customer.y), coffee) < 0.05
        if customer.gone:
            break
    assert reached_coffee and customer.gone
    assert (customer.x, customer.y) == pytest.approx(world.floor.places["street"][:2], abs=0.03)


def test_store_shoppers_walk_the_aisles_clear_of_the_shelves_and_leave():
    sim = simulation("store_shoppers", "perses", seed=3)
    world = sim.world
    shelves = {n: p[:2] for n, p in world.floor.places.items() if n.startswith("shelf_")}
    dwelt = set()
    while world.t < 300.0 and not all(p.gone for p in world.people):
        world.step(0.2)
        for person in world.present_people():
            assert point_segment_distances(person.x, person.y,
                                           world.floor.segments).min() >= BODY_RADIUS
            dwelt |= {(person.id, n) for n, xy in shelves.items()
                      if math.dist(xy, (person.x, person.y)) < 0.01}
    assert all(p.gone for p in world.people)
    assert len(dwelt) >= 15                            # ~4 shelves each
    drawn = [p.step_state for p in world.people]
    assert drawn                                       # the run finished every script


def trajectories(seed):
    sim = simulation("store_shoppers", "perses", seed=seed)
    out = []
    for _ in range(400):
        sim.world.step(0.25)
        out.append(tuple((pid, round(x, 6), round(y, 6)) for pid, x, y in sim.world.ground_truth()))
    return out


def test_store_shoppers_are_the_same_for_a_seed_and_differ_between_seeds():
    first = trajectories(7)
    assert trajectories(7) == first
    assert trajectories(8) != first
