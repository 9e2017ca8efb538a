"""The follow benchmark's judgement of who closed in on a contact (benchmarks/bench_follow.py,
`_robot_closed_in`): by the gap between outlines, so a box-shaped robot (HOROS) driving along
a cart pressed to its side has not driven into it, and its corner sweeping into someone has
(issue 23, HOROS rude seed 2)."""
from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from robots.profile import load_profile
from robots.sim.body import UnicycleBody
from robots.sim.outline import Rectangle
from robots.sim.people import CART_RADIUS
from tests.benchmarks import benchmark_script

HOROS, PERSES = load_profile("horos"), load_profile("perses")


@pytest.fixture(scope="module")
def bench():
    with benchmark_script("bench_follow.py", "bench_follow") as module:
        yield module


def shopper(x, y, cart=()):
    return SimpleNamespace(plan=SimpleNamespace(id="shopper0"), x=x, y=y,
                           cart_circles=lambda: [(cx, cy, CART_RADIUS) for cx, cy in cart])


def world(body, person):
    return SimpleNamespace(body=body, present_people=lambda: [person])


def horos(x, y, th):
    """The simulator's own body of HOROS (its rectangle), where the benchmark reads it."""
    return UnicycleBody(x, y, th, HOROS.limits, HOROS.radius, Rectangle(0.445, 0.393))


def perses(x, y, th):
    return UnicycleBody(x, y, th, PERSES.limits, PERSES.radius)


CONTACT = SimpleNamespace(who="shopper0", part=0)          # their body touched


def cart_contact(circle: int):
    """A contact the simulator found on the shopper's cart (its `circle`-th circle, from 1)."""
    return SimpleNamespace(who="shopper0", part=circle)


def test_driving_along_a_cart_pressed_to_the_side_is_not_driving_into_it(bench):
    # HOROS drives north at 0.2 m/s; the cart's near circle sits 0.09 m ahead of its centre,
    # touching its left side; the shopper pushing it does not move (seed 2 at 69.05 s): the
    # centres near each other (0.03 m/s), the outlines do not
    cart = [(14.13 - 0.49 - 0.45, 16.22), (14.13 - 0.49, 16.22)]
    person = shopper(14.13 - 0.49 - 0.95, 16.22, cart)
    before = {"robot": (14.13, 16.11, math.pi / 2), "shopper0": bench._circles(person)}
    body = horos(14.13, 16.13, math.pi / 2)
    assert not bench._robot_closed_in(cart_contact(2), world(body, person), before)


def test_a_cart_swung_into_the_robot_from_behind_is_not_driven_into(bench):
    # HOROS crowd20 seed 19 at 41.5 -> 41.6 s: HOROS creeps east-south-east at 0.13 m/s; a
    # crosser behind its left swings his cart round into its side (his cart's first circle
    # touches); the crowd pushes him off, and by the tick's end the cart's second circle, ahead
    # of the robot's centre, is the nearest part and the creeping robot nears it
    th = math.radians(-7.2)
    cart_then = [(11.13, 5.19), (11.58, 5.17)]
    cart_now = [(11.27, 5.26), (11.72, 5.17)]
    person = shopper(10.78, 5.35, cart_now)
    before = {"robot": (11.348, 4.653, th), "shopper0": [(10.63, 5.20), *cart_then]}
    body = horos(11.361, 4.651, th)
    nearest_now = min((1, 2), key=lambda k: bench._gap(body, (body.x, body.y, th),
                                                       cart_now[k - 1], CART_RADIUS))
    assert nearest_now == 2
    assert not bench._robot_closed_in(cart_contact(1), world(body, person), before)
    # judged by the part nearest at the tick's end, it was the robot's doing
    assert bench._robot_closed_in(cart_contact(2), world(body, person), before)


def test_a_corner_swept_round_into_someone_standing_is_driven_into(bench):
    # HOROS turns on the spot (its centre stays put) and its front-left corner swings into a
    # person standing beside it
    # (2° in the tick: the corner moves 0.1 m/s, at right angles to the line from the centre)
    hl, hw = 0.445 / 2, 0.393 / 2
    corner = math.hypot(hl, hw)
    th_now = math.radians(10)
    at = math.atan2(hw, hl) + th_now
    cx, cy = corner * math.cos(at), corner * math.sin(at)
    person = shopper(cx - 0.2 * math.sin(at), cy + 0.2 * math.cos(at))
    before = {"robot": (0.0, 0.0, th_now - math.radians(2)), "shopper0": bench._circles(person)}
    assert bench._robot_closed_in(CONTACT, world(horos(0.0, 0.0, th_now), person), before)


def test_a_round_robot_is_judged_by_its_centre_as_before(bench):
    person = shopper(0.46, 0.0)
    before = {"robot": (-0.02, 0.0, 0.0), "shopper0": bench._circles(person)}
    assert bench._robot_closed_in(CONTACT, world(perses(0.0, 0.0, 0.0), person), before)
    walked = {"robot": (0.0, 0.0, 0.0), "shopper0": [(0.50, 0.0)]}
    assert not bench._robot_closed_in(CONTACT, world(perses(0.0, 0.0, 0.0), person), walked)




def walk(speed: float, seconds: float, ahead: float = 1.2, stand: float = 0.0) -> list:
    """(t, x, y) every 0.1 s from 5 s on (where the share begins counting) of a customer
    walking east at `speed` for `seconds` from `ahead` m ahead, then standing `stand` s."""
    path = [(5.0 + k / 10, ahead + speed * k / 10) for k in range(int(seconds * 10) + 1)]
    x = path[-1][1]
    path += [(path[-1][0] + k / 10, x) for k in range(1, int(stand * 10) + 1)]
    return [(t, x, 0.0) for t, x in path]


def test_the_reference_pursuer_keeps_up_with_a_customer_slower_than_its_top_speed(bench):
    path = walk(0.5, 30.0)
    assert bench.pursued_in_band(path, (0.0, 0.0), PERSES.limits) == len(path)


def test_the_reference_pursuer_falls_behind_a_customer_faster_than_its_top_speed(bench):
    """At 1.4 m/s against 0.6 she is 0.3 m beyond the band 0.4 s after the start."""
    assert bench.pursued_in_band(walk(1.4, 30.0), (0.0, 0.0), PERSES.limits) == 4


def test_the_reference_pursuer_backs_off_no_faster_than_the_cap_near_people(bench):
    """She walks back 3 s and stands: at 0.2 m/s the 0.3 m/s cap near people keeps her in
    the band; at 0.5 m/s she closes on it at 0.2 m/s, leaves the band after 1.5 s and is back
    in it 1 s after she stopped (0.3 m regained at 0.3 m/s): 2.5 s outside."""
    assert PERSES.limits.max_speed_near_people == 0.3
    slow, fast = walk(-0.2, 3.0, stand=5.0), walk(-0.5, 3.0, stand=5.0)
    assert bench.pursued_in_band(slow, (0.0, 0.0), PERSES.limits) == len(slow)
    outside = len(fast) - bench.pursued_in_band(fast, (0.0, 0.0), PERSES.limits)
    assert 23 <= outside <= 26


def test_the_capped_reference_slows_near_somebody_ahead_but_not_near_one_left_behind(bench):
    """She walks east at 0.5 m/s from 1.2 m ahead; a shopper stands by the pursuer's way. Held
    to 0.3 m/s while he is within 1.5 m ahead, the pursuer falls behind her; with him behind
    its start (left behind from the first step) it keeps up as without him."""
    path = walk(0.5, 30.0)
    ahead = [((6.0, 0.3),)] * len(path)
    behind = [((-1.0, 0.0),)] * len(path)
    free = bench.pursued_in_band(path, (0.0, 0.0), PERSES.limits)
    assert bench.pursued_in_band(path, (0.0, 0.0), PERSES.limits, behind) == free
    assert bench.pursued_in_band(path, (0.0, 0.0), PERSES.limits, ahead) < free - 20


def test_the_seed_interval_holds_the_pooled_share_and_widens_with_the_spread(bench):
    """Seeds alike: the interval is the share itself; seeds far apart: it spans most of them."""
    same = bench.seed_interval([90, 90, 90, 90], [100] * 4)
    assert same == pytest.approx((0.9, 0.9))
    low, high = bench.seed_interval([50, 95, 90, 85, 92, 88], [100] * 6)
    assert low < 0.833 < high and high - low > 0.05 and high <= 0.95


def test_she_is_out_of_view_behind_a_shelf_and_behind_somebody_not_beside_them(bench):
    # "in view" (the misses, and how long a loss left her out of view) is the camera's line
    # of sight: sampling nine points of the line against the walls' outlines saw through the
    # 1 m deep shelf between aisles A3 and A4 (x 15..16, y 6.5..16.5)
    from robots.sim.floor import load_floor
    store = SimpleNamespace(_walls=load_floor("store").segments)
    her = SimpleNamespace(x=15.5, y=16.9)
    assert not bench.line_of_sight(store, (14.1, 13.9), (her.x, her.y), [her], her)
    her = SimpleNamespace(x=14.0, y=14.0)                   # down aisle A4
    assert bench.line_of_sight(store, (14.0, 8.0), (her.x, her.y), [her], her)
    between = SimpleNamespace(x=14.0, y=11.0)
    assert not bench.line_of_sight(store, (14.0, 8.0), (her.x, her.y), [her, between], her)
    aside = SimpleNamespace(x=14.3, y=11.0)                 # 0.3 m off the line: not hiding her
    assert bench.line_of_sight(store, (14.0, 8.0), (her.x, her.y), [her, aside], her)
