"""The store floor, shoppers (shop), customers who lead (lead), and people hiding each other
from the camera and the laser."""
import math
from dataclasses import replace

import numpy as np
import pytest

from robots.profile import load_profile
from robots.sim.floor import available_floors, load_floor
from robots.sim.people import BODY_RADIUS
from robots.sim.raycast import point_segment_distances
from robots.sim.scenario import parse_scenario
from robots.sim.world import World

from sim_driver import run_until

PERSES = load_profile("perses")
STORE = load_floor("store")
SHELVES = sorted(n for n in STORE.places if n.startswith("shelf_"))


def exact(profile):
    """Noise-free laser and a perfect person detector."""
    return replace(profile, laser=replace(profile.laser, noise=0.0),
                   people_detector=replace(profile.people_detector, noise=0.0, miss_rate=0.0,
                                           false_rate=0.0))


def store_world(people, robot="robot_home", profile=PERSES, seed=0, motion="social"):
    scenario = parse_scenario({"scenario": {"robot": robot, "floor": "store", "motion": motion},
                               "person": people})
    return World(STORE, profile, scenario, seed=seed)


def wall_distance(x, y):
    return float(point_segment_distances(x, y, STORE.segments).min())


def test_store_is_bundled_with_its_places():
    assert "store" in available_floors()
    assert STORE.bounds == (0.0, -3.0, 30.0, 20.0)          # 30 x 20 m and the vestibule
    assert {"robot_home", "entrance", "checkout", "street", "returns"} <= set(STORE.places)
    assert 12 <= len(SHELVES) <= 16
    for aisle in range(1, 7):
        assert {f"aisle{aisle}_south", f"aisle{aisle}_north"} <= set(STORE.places)
    for name, (x, y, _) in STORE.places.items():
        assert wall_distance(x, y) >= 0.5, name              # room to stand and to drive


def test_laser_sees_the_shelves_of_an_aisle_and_the_dead_end():
    profile = exact(PERSES)
    world = World(STORE, profile, None)
    world.body.x, world.body.y, world.body.th = 8.0, 11.0, math.pi / 2   # aisle A2, north
    angles, ranges = world.laser_scan()
    left, ahead, right = (int(np.argmin(np.abs(angles - a)))
                          for a in (math.pi / 2, 0.0, -math.pi / 2))
    assert ranges[left] == pytest.approx(1.0) and ranges[right] == pytest.approx(1.0)
    north_wall = 20.0 - (11.0 + profile.laser.x)          # out the aisle, across the back aisle
    if north_wall <= profile.laser.max_range:
        assert ranges[ahead] == pytest.approx(north_wall)
    else:
        assert ranges[ahead] == np.inf
    world.body.x, world.body.y, world.body.th = 11.0, 9.0, -math.pi / 2  # aisle A3, south
    angles, ranges = world.laser_scan()
    assert ranges[ahead] == pytest.approx(9.0 - profile.laser.x - 6.5)   # the closed end
    sonar = world.sonar_ranges()
    assert np.isfinite(sonar).sum() > 10


def test_people_walk_around_the_shelves_to_every_shelf():
    world = store_world([])
    start = STORE.places["entrance"][:2]
    for name in SHELVES:
        goal = STORE.places[name][:2]
        path = [start] + world.route(start, goal)
        assert path[-1] == goal
        for (x1, y1), (x2, y2) in zip(path, path[1:]):
            for s in np.linspace(0.0, 1.0, 40):
                assert wall_distance(x1 + s * (x2 - x1), y1 + s * (y2 - y1)) >= BODY_RADIUS, name


def test_a_run_of_clear_lines_is_counted_as_one_line_at_a_time_counts_it():
    """`clear_run` (the string pulling's batch) agrees with `clear` line by line, on lines
    inside the store, through shelves and off the floor."""
    from robots.sim.walkways import walk_grid
    grid = walk_grid(STORE)
    rng = np.random.default_rng(3)
    xmin, ymin, xmax, ymax = STORE.bounds
    runs = set()
    for _ in range(200):
        a = (float(rng.uniform(xmin, xmax)), float(rng.uniform(ymin, ymax)))
        near = rng.uniform(-2.0, 2.0, (int(rng.integers(1, 20)), 2)) + a
        far = rng.uniform((xmin - 1, ymin - 1), (xmax + 1, ymax + 1), (3, 2))
        points = [tuple(map(float, p)) for p in np.vstack([near, far])]
        expected = next((k for k, b in enumerate(points) if not grid.clear(a, b)), len(points))
        assert grid.clear_run(a, points) == expected
        runs.add(expected)
    assert len(runs) > 5             # short and long runs both tested


def test_the_way_into_a_dead_end_aisle_comes_from_its_open_end():
    world = store_world([])
    path = world.route(STORE.places["front_aisle"][:2], STORE.places["shelf_canned"][:2])
    assert max(y for _, y in path) > 16.5                    # round by the back aisle


def test_shopper_visits_the_listed_shelves_in_order_and_dwells_facing_them():
    world = store_world([{"id": "s", "at": "entrance", "speed": 1.2, "steps": [
        {"shop": ["shelf_bakery", "shelf_coffee"], "dwell": 4.0}, {"pause": 100.0}]}])
    shopper = world.people[0]
    visits, closest = [], math.inf
    while shopper.index <= 0:
        world.step(0.1)
        closest = min(closest, wall_distance(shopper.x, shopper.y))
        here = next((n for n in ("shelf_bakery", "shelf_coffee")
                     if math.dist((shopper.x, shopper.y), STORE.places[n][:2]) < 0.01), None)
        if here and (not visits or visits[-1][0] != here):
            visits.append((here, world.t, shopper.heading))
        assert world.t < 120.0
    assert [v[0] for v in visits] == ["shelf_bakery", "shelf_coffee"]
    assert visits[0][2] == pytest.approx(STORE.places["shelf_bakery"][2])
    assert closest >= BODY_RADIUS
    assert world.t - visits[1][1] == pytest.approx(4.0, abs=0.15)


def drawn(seed):
    world = store_world([{"id": "s", "at": "entrance", "steps": [
        {"shop": "shelf_", "count": 5, "dwell": [1.0, 3.0]}]}], seed=seed)
    world.step(0.1)
    return world.people[0].step_state["places"]


def test_random_shopping_draws_from_the_prefix_by_the_seed():
    first = drawn(1)
    assert len(first) == 5 and all(name in SHELVES for name in first)
    assert all(a != b for a, b in zip(first, first[1:]))
    assert drawn(1) == first
    assert any(drawn(seed) != first for seed in (2, 3, 4))


def test_shopper_draws_do_not_depend_on_sensor_reads():
    quiet = store_world([{"id": "s", "at": "entrance", "steps": [{"shop": "shelf_"}]}], seed=5)
    busy = store_world([{"id": "s", "at": "entrance", "steps": [{"shop": "shelf_"}]}], seed=5)
    for _ in range(20):
        busy.laser_scan()                                    # draws sensor noise
    quiet.step(0.1)
    busy.step(0.1)
    assert quiet.people[0].step_state["places"] == busy.people[0].step_state["places"]


THREE_AISLES = ["aisle1_south", "aisle1_north", "aisle2_north", "aisle2_south",
                "aisle4_south", "aisle4_north"]


def test_customer_leads_through_three_aisles_clear_of_the_shelves():
    world = store_world([{"id": "c", "at": "entrance", "steps": [
        {"lead": THREE_AISLES, "dwell": 2.0}, {"pause": 100.0}]}], robot=[5.0, 3.0, 90.0])
    customer = world.people[0]
    reached, closest = [], math.inf
    while customer.index <= 0:
        world.body.x, world.body.y = customer.x, customer.y - 1.2   # a robot close behind
        world.step(0.1)
        closest = min(closest, wall_distance(customer.x, customer.y))
        for name in THREE_AISLES:
            if math.dist((customer.x, customer.y), STORE.places[name][:2]) < 0.01 and \
                    name not in reached:
                reached.append(name)
        assert world.t < 200.0
    assert reached == THREE_AISLES
    assert closest >= BODY_RADIUS


def test_lead_waits_for_the_call_and_for_a_robot_left_behind():
    world = store_world([{"id": "c", "at": [5.0, 4.0], "steps": [
        {"lead": ["aisle1_north"], "after_call": True, "wait_beyond": 3.0}]}],
        robot=[5.0, 3.0, 90.0])
    customer = world.people[0]
    world.step(5.0)
    assert (customer.x, customer.y) == (5.0, 4.0)
    world.say("I will follow you")
    run_until(world, lambda w: customer.y > 5.9)               # walks off; the robot stays
    world.step(5.0)
    assert customer.speed == 0.0 and customer.y == pytest.approx(3.0 + 3.0, abs=0.06)
    while customer.index == 0:                                 # the robot catches up
        world.body.y = customer.y - 1.5
        world.step(0.1)
        assert world.t < 60.0
    assert customer.y == pytest.approx(16.5)


# -- occlusion ---------------------------------------------------------------------------

def customer_beams(world, distance):
    """Laser beams that end on the customer's legs, `distance` m straight ahead."""
    angles, ranges = world.laser_scan()
    laser_x = world.profile.laser.x
    on_legs = np.abs(ranges - (distance - laser_x - 0.06)) < 0.07
    return int(np.sum(on_legs & (np.abs(angles) < 0.1)))


def test_a_person_in_between_hides_another_from_the_camera_and_partly_from_the_laser():
    profile = exact(PERSES)
    robot = [14.0, 4.75, 0.0]
    alone = store_world([{"id": "c", "at": [17.0, 4.75]}], robot=robot, profile=profile)
    alone.step(0.05)
    assert alone.detect_people() == [pytest.approx((3.0, 0.0))]
    hidden = store_world([{"id": "c", "at": [17.0, 4.75]}, {"id": "s", "at": [15.5, 4.75]}],
                         robot=robot, profile=profile)
    hidden.step(0.05)
    assert hidden.detect_people() == [pytest.approx((1.5, 0.0))]   # only the one in front
    assert customer_beams(hidden, 3.0) < customer_beams(alone, 3.0)
    aside = store_world([{"id": "c", "at": [17.0, 4.75]}, {"id": "s", "at": [15.5, 4.15]}],
                        robot=robot, profile=profile)
    aside.step(0.05)
    assert len(aside.detect_people()) == 2


def test_a_passing_shopper_hides_the_customer_for_about_two_seconds():
    profile = exact(PERSES)
    world = store_world([
        {"id": "c", "at": [17.0, 4.75]},
        {"id": "s", "at": [15.5, 3.35], "speed": 1.0,
         "steps": [{"pause": 2.0}, {"walk": [[15.5, 4.75]]}, {"pause": 1.6},
                   {"walk": [[15.5, 6.2]]}]}], robot=[14.0, 4.75, 0.0], profile=profile)
    hidden = 0
    for _ in range(100):
        world.step(0.1)
        if not any(abs(x - 3.0) < 0.1 for x, _ in world.detect_people()):
            hidden += 1
    assert 1.8 <= hidden * 0.1 <= 2.4


def test_a_shopper_with_a_cart_hides_the_customer_from_the_laser_too():
    profile = exact(PERSES)
    robot = [14.0, 4.75, 0.0]
    alone = store_world([{"id": "c", "at": [17.0, 4.75]}], robot=robot, profile=profile)
    alone.step(0.05)
    cart = {"id": "s", "at": [15.5, 3.6], "cart": True, "speed": 1.0,
            "steps": [{"walk": [[15.5, 4.1]]}, {"pause": 100.0}]}   # the cart crosses ahead
    world = store_world([{"id": "c", "at": [17.0, 4.75]}, cart], robot=robot, profile=profile)
    run_until(world, lambda w: w.people[1].index == 1)
    shopper = world.people[1]
    assert [round(c[1], 2) for c in shopper.cart_circles()] == [4.6, 5.05]
    assert customer_beams(alone, 3.0) >= 4 and customer_beams(world, 3.0) == 0
    # the camera looks over the cart and sees both
    assert world.detect_people() == [pytest.approx((3.0, 0.0)), pytest.approx((1.5, -0.65))]
    shopper.heading = 0.0                                   # turning to a shelf: the cart stays
    assert [round(c[1], 2) for c in shopper.cart_circles()] == [4.6, 5.05]


def test_the_robot_bumping_a_cart_is_a_contact_with_its_shopper():
    cart = {"id": "s", "at": [14.0, 3.9], "cart": True, "steps": [{"walk": [[14.0, 4.0]]}]}
    world = store_world([cart], robot=[14.8, 5.2, -120.0], motion="scripted")  # stands still
    world.body.set_command(0.2, 0.0)
    world.step(6.0)
    assert world.body.stalled
    contact, = world.measures.contacts
    assert (contact.kind, contact.who, contact.robot_moving) == ("person", "s", True)
    assert math.hypot(world.body.x - 14.0, world.body.y - 3.9) > 0.2 + PERSES.radius + 0.05


def test_the_camera_reports_each_persons_own_look_with_noise():
    from robots.sim.appearance import BINS, appearance_of
    from skills.people.appearance import SAME_PERSON, distance
    robot = [14.0, 4.75, 0.0]
    people = [{"id": "c", "at": [17.0, 4.75]}, {"id": "x", "at": [16.0, 3.9]}]
    # two people who dress differently (as most pairs do; some pairs look alike, as "c" and
    # "s" do at 0.23)
    assert distance(appearance_of("c"), appearance_of("x")) > 0.4
    world = store_world(people, robot=robot, profile=exact(PERSES))
    world.step(0.05)
    looks = {}
    for _ in range(50):
        for x, y, look in world.person_detections():
            who = "c" if x > 2.5 else "x"
            looks.setdefault(who, []).append(look)
    assert {len(v) for v in looks.values()} == {50}
    assert all(len(look) == BINS and sum(look) == pytest.approx(1.0) for look in looks["c"])
    assert len(set(looks["c"])) == 50                          # every view has its own noise
    own = [distance(look, appearance_of("c")) for look in looks["c"]]
    other = [distance(look, appearance_of("c")) for look in looks["x"]]
    assert max(own) <= SAME_PERSON < min(other)
    assert np.allclose(appearance_of("c"), store_world(people, robot=robot).appearances["c"])


def test_appearance_draws_no_number_from_the_worlds_other_random_streams(monkeypatch):
    # the same world once with the camera's looks drawn as they are and once with looks that
    # draw nothing at all: the world's own random stream, and so every position, stays the same
    import robots.sim.world as world_module
    people = [{"id": "c", "at": [17.0, 4.75]}, {"id": "x", "at": [16.0, 3.9]}]
    profile = replace(PERSES, people_detector=replace(PERSES.people_detector, false_rate=1.0))

    def positions(world):
        seen = []
        for _ in range(30):
            world.step(0.1)
            seen.append([(x, y) for x, y, _ in world.person_detections()])
        return seen, world.rng.bit_generator.state

    drawn = positions(store_world(people, robot=[14.0, 4.75, 0.0], profile=profile, seed=3))
    monkeypatch.setattr(world_module, "observed", lambda true, rng: tuple(true))
    monkeypatch.setattr(world_module, "anyone", lambda rng: (1.0,))
    fixed = positions(store_world(people, robot=[14.0, 4.75, 0.0], profile=profile, seed=3))
    assert any(frame for frame in drawn[0]) and drawn == fixed
