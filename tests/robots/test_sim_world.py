"""The world's sensors from robot_home, people as the sensors see them, determinism."""
import math
from dataclasses import replace

import numpy as np
import pytest

from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.scenario import parse_scenario
from robots.sim.world import World

HOROS = load_profile("horos")
PERSES = load_profile("perses")
FLOOR = load_floor("office")


def standing(*people, robot="robot_home"):
    """A scenario of people standing still at the given (id, x, y)."""
    return parse_scenario({"scenario": {"robot": robot},
                           "person": [{"id": pid, "at": [x, y]} for pid, x, y in people]})


def exact(profile):
    """The profile with noise-free sensors and a perfect person detector."""
    return replace(profile, laser=replace(profile.laser, noise=0.0),
                   people_detector=replace(profile.people_detector, noise=0.0, miss_rate=0.0,
                                           false_rate=0.0))


def test_robot_starts_at_robot_home():
    world = World(FLOOR, HOROS)
    assert (world.body.x, world.body.y, world.body.th) == (0.0, -0.75, math.pi / 2)


def test_sonar_sees_the_hallway_walls_from_robot_home():
    ranges = World(FLOOR, HOROS).sonar_ranges()
    assert ranges.shape == (16,)
    # sonar 3 (10 deg) looks across the hallway from x=0.166 ahead of the centre
    assert ranges[3] == pytest.approx(1.2 - (-0.75 + 0.166), abs=1e-9)
    # sonar 11 (-170 deg) looks at the wall behind, 0.255 behind the centre
    assert ranges[11] == pytest.approx(-0.75 - 0.255 - (-1.2), abs=1e-9)


def test_perses_sonar_ring_reads_one_range_per_sonar_within_max_range():
    ranges = World(FLOOR, PERSES).sonar_ranges()
    assert ranges.shape == (48,)
    finite = ranges[np.isfinite(ranges)]
    assert finite.size > 20 and np.all(finite <= PERSES.sonar.max_range)


def test_laser_straight_ahead_reads_the_far_wall():
    world = World(FLOOR, exact(HOROS))
    angles, ranges = world.laser_scan()
    assert angles.shape == ranges.shape == (181,)
    assert angles[0] == pytest.approx(-math.pi / 2) and angles[-1] == pytest.approx(math.pi / 2)
    assert ranges[90] == pytest.approx(1.2 - (-0.75 + 0.16))
    # sideways (along the hallway) the laser sees the north/south walls or far ends
    assert np.all(ranges[np.isfinite(ranges)] <= HOROS.laser.max_range)


def test_laser_noise_has_the_profile_sigma():
    world = World(FLOOR, HOROS, seed=3)
    samples = np.array([world.laser_scan()[1][90] for _ in range(400)])
    assert samples.std() == pytest.approx(HOROS.laser.noise, rel=0.2)
    assert samples.mean() == pytest.approx(1.2 - (-0.75 + 0.16), abs=0.003)


def test_laser_sees_two_legs_and_sonar_one_body():
    world = World(FLOOR, exact(HOROS), standing(("p", 0.0, 0.5)))
    world.step(0.05)
    angles, ranges = world.laser_scan()
    near = np.flatnonzero(ranges < 1.5)
    assert near.size > 0
    # two separate groups of beams (the legs) with a gap between them
    assert np.any(np.diff(near) > 1)
    assert ranges.min() == pytest.approx(0.5 - (-0.75 + 0.16) - 0.06, abs=0.02)
    assert world.sonar_ranges()[3] == pytest.approx(0.5 - 0.2 - (-0.75 + 0.166), abs=0.02)


def test_detect_people_in_robot_frame_when_exact():
    world = World(FLOOR, exact(HOROS), standing(("p", 1.0, 0.25)))
    world.step(0.05)
    (x, y), = world.detect_people()
    # robot at (0, -0.75) facing +y: the person is 1.0 m ahead and 1.0 m to the right
    assert (x, y) == pytest.approx((1.0, -1.0))


def test_detector_respects_range_field_of_view_and_walls():
    profile = exact(HOROS)
    people = standing(("far", 6.0, 0.0), ("behind_wall", 0.0, 3.0), ("visible", -2.0, 0.0))
    world = World(FLOOR, profile, people)
    world.step(0.05)
    assert world.detect_people() == [pytest.approx((0.75, 2.0))]
    narrow = replace(profile, people_detector=replace(profile.people_detector,
                                                      fov=math.radians(60)))
    world = World(FLOOR, narrow, people)
    world.step(0.05)
    assert world.detect_people() == []


def test_detector_misses_and_false_positives_follow_the_rates():
    profile = replace(HOROS, people_detector=replace(HOROS.people_detector, miss_rate=0.3,
                                                     false_rate=0.5))
    world = World(FLOOR, profile, standing(("p", 1.0, 0.25)), seed=11)
    world.step(0.05)
    frames = [world.detect_people() for _ in range(2000)]
    real = sum(any(math.hypot(x - 1.0, y + 1.0) < 0.3 for x, y in f) for f in frames)
    total = sum(len(f) for f in frames)
    assert real / 2000 == pytest.approx(0.7, abs=0.05)
    assert (total - real) / 2000 == pytest.approx(0.5, abs=0.08)
    spec = profile.people_detector
    for frame in frames:
        for x, y in frame:
            assert math.hypot(x, y) <= spec.range + 0.5


def test_ground_truth_lists_people_in_the_world():
    world = World(FLOOR, HOROS, standing(("a", 1.0, 0.0), ("b", -1.0, 0.0)))
    assert world.ground_truth() == []            # nobody before the first step
    world.step(0.1)
    assert world.ground_truth() == [("a", 1.0, 0.0), ("b", -1.0, 0.0)]


def test_step_uses_substeps_and_runs_hooks_after_each():
    world = World(FLOOR, HOROS)
    calls = []
    world.hooks.append(lambda w, dt: calls.append((round(w.t, 9), dt)))
    world.step(0.12)
    assert [t for t, _ in calls] == [0.04, 0.08, 0.12]
    assert all(dt == pytest.approx(0.04) for _, dt in calls)
    assert world.t == pytest.approx(0.12)


def run(seed):
    scenario = parse_scenario({"person": [
        {"id": "w", "at": [5.0, 0.3], "speed": 0.8, "steps": [{"walk": [[-5.0, 0.3]]}]}]})
    world = World(FLOOR, HOROS, scenario, seed=seed)
    world.body.set_command(0.0, 0.2)
    out = []
    for _ in range(50):
        world.step(0.1)
        out.append((world.laser_scan()[1].copy(), world.detect_people()))
    return out


def test_same_seed_same_readings_different_seed_different():
    a, b, c = run(5), run(5), run(6)
    for (la, da), (lb, db) in zip(a, b):
        np.testing.assert_array_equal(la, lb)
        assert da == db
    assert any(not np.array_equal(la, lc) for (la, _), (lc, _) in zip(a, c))


def test_readings_follow_a_body_placed_by_hand():
    world = World(FLOOR, exact(HOROS))
    before = world.sonar_ranges()[3]
    world.body.y = -0.25                        # half a metre closer to the far wall
    assert world.sonar_ranges()[3] == pytest.approx(before - 0.5)
    assert world.laser_scan()[1][90] == pytest.approx(1.2 - (-0.25 + 0.16))


def test_without_a_scenario_the_robot_starts_at_robot_home_or_the_origin():
    from robots.sim.floor import parse_floor
    bare = parse_floor({"floor": {"walls": [[5.0, -5.0, 5.0, 5.0]]}})
    world = World(bare, HOROS)
    assert (world.body.x, world.body.y, world.body.th) == (0.0, 0.0, 0.0)
    assert world.sonar_ranges()[3] == pytest.approx(5.0 - 0.166, abs=1e-3)


def test_a_look_alike_has_the_appearance_of_the_person_she_dresses_like():
    from robots.sim.appearance import appearance_of
    from robots.sim.floor import load_floor
    from robots.profile import load_profile
    from robots.sim.scenario import parse_scenario
    from robots.sim.world import World
    scenario = parse_scenario({"person": [{"id": "tara", "at": [0, 0]},
                                          {"id": "tess", "at": [2, 0], "looks_like": "tara"},
                                          {"id": "sam", "at": [4, 0]}]})
    world = World(load_floor("office"), load_profile("perses"), scenario, seed=0)
    assert list(world.appearances["tess"]) == list(appearance_of("tara"))
    assert list(world.appearances["sam"]) != list(appearance_of("tara"))


def fresh_cast(world):
    """Sonar and noise-free laser ranges cast now, without the kept scene."""
    return world._sonar_cast(), world._laser_cast()


def test_a_kept_scene_gives_the_ranges_a_fresh_cast_gives():
    """The sensors cast again only when the body or a circle moved (`World._same_scene`)."""
    world = World(FLOOR, exact(HOROS), standing(("p", 1.0, 0.4)))
    for _ in range(3):                          # standing: the same scene substep after substep
        world.step(0.05)
        sonar, laser = fresh_cast(world)
        np.testing.assert_array_equal(world.sonar_ranges(), sonar)
        np.testing.assert_array_equal(world.laser_scan()[1], laser)
    kept = world._scenes["laser"][2]
    world.people[0].x = 0.3                     # someone moved in front of the robot
    world.step(0.05)
    sonar, laser = fresh_cast(world)
    np.testing.assert_array_equal(world.sonar_ranges(), sonar)
    np.testing.assert_array_equal(world.laser_scan()[1], laser)
    assert not np.array_equal(laser, kept)
    world.body.th += 0.3                        # the body turned by hand
    np.testing.assert_array_equal(world.laser_scan()[1], world._laser_cast())
