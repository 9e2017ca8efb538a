"""Ray casting against hand-computed geometry, and properties of hits."""
import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from robots.sim.raycast import cast_rays, point_segment_distances, segment_distances

NO_SEGMENTS = np.zeros((0, 4))
NO_CIRCLES = np.zeros((0, 3))
ORIGIN = np.zeros((1, 2))


def test_wall_straight_ahead_at_known_distance():
    wall = np.array([[2.0, -1.0, 2.0, 1.0]])
    assert cast_rays(ORIGIN, [0.0], wall, NO_CIRCLES, 8.0) == [2.0]


def test_wall_at_an_angle_reads_the_slant_distance():
    wall = np.array([[2.0, -5.0, 2.0, 5.0]])
    ranges = cast_rays(ORIGIN, [math.radians(60)], wall, NO_CIRCLES, 8.0)
    assert math.isclose(ranges[0], 2.0 / math.cos(math.radians(60)), rel_tol=1e-12)


def test_circle_reads_distance_to_its_near_side():
    circle = np.array([[3.0, 0.0, 0.5]])
    assert math.isclose(cast_rays(ORIGIN, [0.0], NO_SEGMENTS, circle, 8.0)[0], 2.5)


def test_tangent_offset_ray_hits_circle_off_centre():
    circle = np.array([[4.0, 0.3, 0.5]])
    expected = 4.0 - math.sqrt(0.5 ** 2 - 0.3 ** 2)
    assert math.isclose(cast_rays(ORIGIN, [0.0], NO_SEGMENTS, circle, 8.0)[0], expected)


def test_miss_behind_beside_and_beyond_range_is_inf():
    wall = np.array([[2.0, -1.0, 2.0, 1.0]])
    circle = np.array([[0.0, 3.0, 0.2]])
    angles = [math.pi, math.radians(60), 0.0]
    ranges = cast_rays(np.zeros((3, 2)), angles, wall, circle, 8.0)
    assert ranges[0] == np.inf                       # wall is behind
    assert ranges[1] == np.inf                       # passes beside the wall's end and the circle
    assert cast_rays(ORIGIN, [0.0], wall, NO_CIRCLES, 1.5)[0] == np.inf   # beyond max range


def test_parallel_ray_does_not_hit():
    wall = np.array([[0.0, 1.0, 5.0, 1.0]])
    assert cast_rays(ORIGIN, [0.0], wall, NO_CIRCLES, 8.0)[0] == np.inf


def test_origin_inside_circle_reads_zero():
    circle = np.array([[0.1, 0.0, 0.5]])
    assert cast_rays(ORIGIN, [1.0], NO_SEGMENTS, circle, 8.0)[0] == 0.0


def test_nearest_obstacle_wins_and_rays_are_independent():
    walls = np.array([[2.0, -1.0, 2.0, 1.0], [4.0, -1.0, 4.0, 1.0], [-3.0, -1.0, -3.0, 1.0]])
    circle = np.array([[1.0, 0.0, 0.25]])
    origins = np.array([[0.0, 0.0], [0.0, 0.0], [0.0, 0.5]])
    ranges = cast_rays(origins, [0.0, math.pi, 0.0], walls, circle, 8.0)
    np.testing.assert_allclose(ranges, [0.75, 3.0, 2.0])


def test_point_segment_distances():
    walls = np.array([[0.0, 1.0, 2.0, 1.0], [3.0, 0.0, 3.0, 2.0]])
    np.testing.assert_allclose(point_segment_distances(1.0, 0.0, walls), [1.0, 2.0])
    np.testing.assert_allclose(point_segment_distances(-1.0, 1.0, walls)[0], 1.0)


coordinate = st.floats(-5.0, 5.0)


@settings(max_examples=150, deadline=None)
@given(x1=coordinate, y1=coordinate, x2=coordinate, y2=coordinate,
       ox=coordinate, oy=coordinate, angle=st.floats(-math.pi, math.pi))
@example(x1=0.5, y1=5e-324, x2=0.0, y2=0.0, ox=1.0, oy=0.0, angle=0.0)   # behind it (was hit)
def test_hits_lie_on_the_wall_and_ray(x1, y1, x2, y2, ox, oy, angle):
    if math.hypot(x2 - x1, y2 - y1) < 1e-3:
        return
    wall = np.array([[x1, y1, x2, y2]])
    r = cast_rays(np.array([[ox, oy]]), [angle], wall, NO_CIRCLES, 100.0)[0]
    if r == np.inf:
        return
    hx, hy = ox + r * math.cos(angle), oy + r * math.sin(angle)
    assert r >= 0.0
    assert point_segment_distances(hx, hy, wall)[0] < 1e-6


@settings(max_examples=150, deadline=None)
@given(cx=coordinate, cy=coordinate, radius=st.floats(0.05, 1.0),
       angle=st.floats(-math.pi, math.pi))
def test_circle_hits_lie_on_the_circle(cx, cy, radius, angle):
    r = cast_rays(ORIGIN, [angle], NO_SEGMENTS, np.array([[cx, cy, radius]]), 100.0)[0]
    if r == np.inf or r == 0.0:
        return
    hx, hy = r * math.cos(angle), r * math.sin(angle)
    assert math.isclose(math.hypot(hx - cx, hy - cy), radius, abs_tol=1e-6)


def test_one_origin_for_all_rays_and_kept_wall_hits_give_the_very_same_ranges():
    """A laser passes one origin for all its beams, and reuses its wall hits while it stands:
    both shortcuts must give bit-for-bit what a ray per origin gives (the kept states rest on it)."""
    rng = np.random.default_rng(1)
    for _ in range(100):
        origin, n = rng.uniform(-5, 5, 2), int(rng.integers(1, 200))
        angles = rng.uniform(-4, 4, n)
        segments = rng.uniform(-8, 8, (int(rng.integers(0, 40)), 4))
        circles = np.column_stack([rng.uniform(-6, 6, (15, 2)), rng.uniform(0.02, 0.5, 15)])
        per_ray = cast_rays(np.broadcast_to(origin, (n, 2)), angles, segments, circles, 7.0)
        one = cast_rays(origin[None, :], angles, segments, circles, 7.0)
        kept = cast_rays(origin[None, :], angles, None, circles, 7.0,
                         segment_distances(origin[None, :], angles, segments))
        assert np.isfinite(per_ray).any() or not len(segments)
        assert np.array_equal(per_ray, one)
        assert np.array_equal(per_ray, kept)
