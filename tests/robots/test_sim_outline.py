"""HOROS's body in the simulated world is its rectangle (0.445 m × 0.393 m) turned with the pose:
gaps to walls and people, the collision stop, and the contacts the measures count."""
import math

import numpy as np
import pytest

from robots.profile import load_profile
from robots.sim.body import Obstacles, UnicycleBody
from robots.sim.outline import Rectangle

HOROS = load_profile("horos")
BOX = Rectangle(0.445, 0.393)
NO_CIRCLES = np.zeros((0, 3))


def wall(x1, y1, x2, y2) -> np.ndarray:
    return np.array([[x1, y1, x2, y2]], dtype=float)


def test_the_gap_to_a_wall_is_from_the_side_the_front_or_a_corner():
    assert BOX.gap_to_segments(0, 0, 0, wall(-2, 0.5, 2, 0.5)) == pytest.approx(0.5 - 0.1965)
    assert BOX.gap_to_segments(0, 0, 0, wall(0.5, -2, 0.5, 2)) == pytest.approx(0.5 - 0.2225)
    # turned 90°: the long side now faces the wall to the north
    assert BOX.gap_to_segments(0, 0, math.pi / 2, wall(-2, 0.5, 2, 0.5)) == pytest.approx(
        0.5 - 0.2225)
    # a wall end pointing at a corner: the gap is from the corner, not the bounding circle
    corner = math.hypot(0.2225, 0.1965)
    end = 0.4 / math.sqrt(2)
    assert BOX.gap_to_segments(0, 0, math.pi / 4 - math.atan2(0.1965, 0.2225),
                               wall(end, end, 2, 2)) == pytest.approx(0.4 - corner, abs=1e-9)


def test_a_wall_across_the_rectangle_is_overlap_deepest_at_the_centre():
    shallow = BOX.gap_to_segments(0, 0, 0, wall(0.2, -1, 0.2, 1))
    deep = BOX.gap_to_segments(0, 0, 0, wall(0.0, -1, 0.0, 1))
    assert shallow == pytest.approx(-0.0225, abs=1e-6)
    assert deep == pytest.approx(-0.1965, abs=1e-6) and deep < shallow


def test_the_gap_to_a_person_depends_on_the_heading():
    person = np.array([[0.0, 0.6, 0.2]])
    side = BOX.gap_to_circles(0, 0, 0, person)[0]
    end = BOX.gap_to_circles(0, 0, math.pi / 2, person)[0]
    assert side == pytest.approx(0.6 - 0.1965 - 0.2)
    assert end == pytest.approx(0.6 - 0.2225 - 0.2)


def horos_body(x=0.0, y=0.0, th=0.0) -> UnicycleBody:
    return UnicycleBody(x, y, th, HOROS.limits, HOROS.radius, BOX)


def test_horos_drives_through_a_gap_its_bounding_circle_would_not_pass():
    """A 0.46 m gap between two posts: the 0.393 m wide body passes it (the 0.52 m circle
    stopped at it)."""
    posts = Obstacles(np.vstack([wall(1.0, 0.23, 1.0, 1.0), wall(1.0, -0.23, 1.0, -1.0)]),
                      NO_CIRCLES)
    for body, passes in ((horos_body(), True),
                         (UnicycleBody(0, 0, 0, HOROS.limits, HOROS.radius), False)):
        body.set_command(0.3, 0.0)
        for _ in range(200):
            body.step(0.05, posts)
        assert (body.x > 1.5) is passes
        assert body.stalled is not passes


def test_horos_turning_beside_a_wall_stops_when_a_corner_would_sweep_into_it():
    """The side 0.05 m from a wall: turning on the spot brings a corner (0.297 m from the
    centre) into the wall, so the body stops; the bounding circle (0.26 m) saw nothing."""
    beside = Obstacles(wall(-2, 0.2465, 2, 0.2465), NO_CIRCLES)
    body = horos_body()
    body.set_command(0.0, 1.0)
    for _ in range(40):
        body.step(0.05, beside)
    assert body.stalled and body.clearance(body.x, body.y, beside) >= -0.01
    assert abs(body.th) < math.radians(20)


def test_the_world_gives_horos_its_rectangle_and_perses_its_circle():
    from robots.sim.floor import load_floor
    from robots.sim.world import World
    horos = World(load_floor("office"), HOROS)
    perses = World(load_floor("office"), load_profile("perses"))
    assert horos.body.rectangle is not None
    assert (horos.body.rectangle.half_length, horos.body.rectangle.half_width) == (
        pytest.approx(0.2225), pytest.approx(0.1965))
    assert perses.body.rectangle is None


def test_the_measures_count_a_corner_touching_a_wall_as_a_contact():
    """HOROS at robot_home (0, -0.75) facing north, 0.45 m from the hallway's south wall at
    y = -1.2: moved to where its rear corner, not its centre's circle, reaches the wall."""
    from robots.sim.floor import load_floor
    from robots.sim.world import World
    world = World(load_floor("office"), HOROS)
    world.step(0.1)
    assert world.measures.contact_count("wall") == 0
    # turned so that a front corner points south: it reaches 0.297 m below the centre, where
    # a circle of 0.26 m does not
    world.body.x, world.body.y, world.body.th = 0.0, -1.2 + 0.29, -(
        math.pi / 2 - math.atan2(0.1965, 0.2225))
    world.step(0.05)
    assert world.measures.min_wall_clearance < 0.0 < 0.29 - HOROS.radius
    assert world.measures.contact_count("wall") == 1


def test_the_bound_is_below_every_exact_gap_and_the_stop_rule_is_unchanged():
    """The cheap bound (centre distance less the half diagonal) never exceeds the exact gap
    to walls or circles, whatever the heading, so deciding by it alone changes nothing."""
    rng = np.random.default_rng(7)
    body = UnicycleBody(0.0, 0.0, 0.0, HOROS.limits, HOROS.radius, BOX)
    for _ in range(400):
        x, y, th = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-math.pi, math.pi)
        segments = rng.uniform(-1.5, 1.5, (int(rng.integers(1, 6)), 4))
        circles = np.c_[rng.uniform(-1.5, 1.5, (3, 2)), rng.uniform(0.05, 0.3, 3)]
        exact_walls = BOX.gap_to_segments(x, y, th, segments)
        exact_circles = float(BOX.gap_to_circles(x, y, th, circles).min())
        assert body.gap_bound(segments, None, x, y) <= exact_walls
        assert body.gap_bound(segments, circles, x, y) <= min(exact_walls, exact_circles)
        obstacles = Obstacles(segments, circles)
        after = body.clearance(x, y, obstacles, th)
        expected = after < 0.0 and after < body.clearance(body.x, body.y, obstacles, body.th)
        assert body._blocked(x, y, obstacles, th) == expected
