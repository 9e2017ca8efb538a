"""The controller's CPU cuts change no bit: its rewritten kernels against the code they
replaced (kept here verbatim), on poses inside, at the edge of and off the map."""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from skills.navigation.controller import (KD_TREE_FROM, NEAREST_READINGS, SQUARES_UP_TO,
                                          LocalController, _arc, _linspace, _nearest_distance,
                                          _PathAhead, _project, _resample, _rollout_grid, _speeds)
from skills.navigation.footprint import Footprint
from tests.skills.test_navigation_controller import CONTROLLER, COSTMAP, LIMITS, ROOM


def old_map_clearance(controller, x, y):
    """`LocalController._map_clearance` before the cut: np.clip and 2-D fancy indexing."""
    grid, field = controller.costmap.grid, controller.costmap.clearance
    fx = (np.asarray(x, float) - grid.origin[0]) / grid.resolution - 0.5
    fy = (np.asarray(y, float) - grid.origin[1]) / grid.resolution - 0.5
    c0, r0 = np.floor(fx).astype(int), np.floor(fy).astype(int)
    tx, ty = fx - c0, fy - r0
    rows, cols = field.shape
    inside = (r0 >= 0) & (c0 >= 0) & (r0 + 1 < rows) & (c0 + 1 < cols)
    r0c, c0c = np.clip(r0, 0, rows - 2), np.clip(c0, 0, cols - 2)
    f00, f01 = field[r0c, c0c], field[r0c, c0c + 1]
    f10, f11 = field[r0c + 1, c0c], field[r0c + 1, c0c + 1]
    d = ((1 - tx) * (1 - ty) * f00 + tx * (1 - ty) * f01
         + (1 - tx) * ty * f10 + tx * ty * f11)
    d = np.minimum(d, np.minimum(np.minimum(f00, f01), np.minimum(f10, f11))
                   + grid.resolution)
    return np.where(inside, d, 0.0)


def old_project(points, samples):
    dx = points[:, None, 0] - samples[None, :, 0]
    dy = points[:, None, 1] - samples[None, :, 1]
    nearest = (dx * dx + dy * dy).argmin(axis=1)
    rows = np.arange(len(points))
    return nearest * 0.05, np.hypot(dx[rows, nearest], dy[rows, nearest])


def test_map_clearance_is_bit_identical_inside_at_the_edge_and_off_the_map():
    rng = np.random.default_rng(7)
    height, width = (n * ROOM.resolution for n in ROOM.occupied.shape)
    x = rng.uniform(-0.5, width + 0.5, (105, 20))
    y = rng.uniform(-0.5, height + 0.5, (105, 20))
    x[0, :5] = [0.0, 0.025, width - 0.025, width, -1e-12]     # cell centres and edges
    new, old = CONTROLLER._map_clearance(x, y), old_map_clearance(CONTROLLER, x, y)
    assert new.shape == old.shape
    assert new.tobytes() == old.tobytes()
    assert (old == 0.0).any() and (old > 0.0).any()           # both off and on the map


def test_projection_and_resampling_are_bit_identical():
    rng = np.random.default_rng(3)
    path = np.cumsum(rng.normal(0.0, 0.2, (12, 2)), axis=0)
    window, _ = _resample(path, 0.05, 3.0)
    assert np.array_equal(window, _resample(path, 0.05, 3.0, _arc(path))[0])
    points = rng.normal(0.0, 1.0, (200, 2))
    for new, old in zip(_project(points, window), old_project(points, window)):
        assert new.tobytes() == old.tobytes()


def test_one_points_clearance_in_floats_is_the_arrays_to_the_bit():
    """A single point (the robot's pose, once a tick) takes the plain-float path: the same
    value as the same point among others, on, at the edge of and off the map."""
    rng = np.random.default_rng(8)
    height, width = (n * ROOM.resolution for n in ROOM.occupied.shape)
    x = np.concatenate([rng.uniform(-0.5, width + 0.5, 2000), [0.0, 0.025, width - 0.025, width,
                                                               -1e-12, 0.075, width - 0.075]])
    y = np.concatenate([rng.uniform(-0.5, height + 0.5, 2000), [0.025, 0.0, 0.075, 0.3,
                                                                0.3, height - 0.075, height]])
    many = old_map_clearance(CONTROLLER, x, y)
    one = np.array([CONTROLLER._map_clearance(np.array([a]), np.array([b]))[0]
                    for a, b in zip(x.tolist(), y.tolist())])
    assert one.tobytes() == many.tobytes()
    assert (many == 0.0).any() and (many > 0.0).any()


def test_map_clearance_keeps_the_shape_of_a_single_point_and_a_row():
    for x, y in [(1.0, 1.0), (np.array([1.0]), np.array([1.0])), (-3.0, 1.0),
                 (np.array([0.4, 1.3, -2.0]), np.array([[0.7], [1.1]]))]:
        new, old = CONTROLLER._map_clearance(x, y), old_map_clearance(CONTROLLER, x, y)
        assert new.shape == old.shape
        assert new.tobytes() == old.tobytes()


def test_nearest_distance_without_the_tree_is_the_trees_to_the_bit():
    """Beyond KD_TREE_FROM readings the distances are the k-d tree's (sqrt of dx*dx + dy*dy,
    not np.hypot's), with or without the tree."""
    rng = np.random.default_rng(11)
    for count in range(KD_TREE_FROM + 1, SQUARES_UP_TO + 1, 5):
        points = rng.uniform(0.0, 3.0, (count, 2))
        for shape in [(1,), (7,), (120, 20)]:
            px, py = rng.uniform(-0.5, 3.5, shape), rng.uniform(-0.5, 3.5, shape)
            px.flat[0], py.flat[0] = points[0]                   # on a reading
            old, _ = cKDTree(points).query(np.column_stack([px.ravel(), py.ravel()]))
            new = _nearest_distance(px, py, points)
            assert new.shape == shape
            assert new.tobytes() == old.reshape(shape).tobytes()


def test_a_few_readings_give_the_plain_distances_for_any_number_of_poses():
    rng = np.random.default_rng(12)
    for count in range(1, KD_TREE_FROM + 1):
        points = rng.uniform(0.0, 3.0, (count, 2))
        for shape in [(1,), (40,), (120, 20)]:
            px, py = rng.uniform(-0.5, 3.5, shape), rng.uniform(-0.5, 3.5, shape)
            old = np.hypot(px[..., None] - points[:, 0], py[..., None] - points[:, 1]).min(-1)
            assert _nearest_distance(px, py, points).tobytes() == old.tobytes()


def test_a_rectangle_against_up_to_nearest_readings_needs_no_tree():
    """The tree preselected all of them (k = their number): the same least gap."""
    box = LocalController(COSTMAP, LIMITS, footprint=Footprint("rectangle", 0.3, 0.45, 0.39))
    rng = np.random.default_rng(13)
    for count in range(KD_TREE_FROM + 1, NEAREST_READINGS + 1):
        points = rng.uniform(0.0, 3.0, (count, 2))
        px, py = rng.uniform(0.0, 3.0, (60, 20)), rng.uniform(0.0, 3.0, (60, 20))
        pth = rng.uniform(-np.pi, np.pi, (60, 20))
        _, index = cKDTree(points).query(np.column_stack([px.ravel(), py.ravel()]), k=count)
        old = box.footprint.gap_to_points(px, py, pth, points[index.reshape(60, 20, count)])
        assert box._points_gap(px, py, pth, points).tobytes() == old.tobytes()


def old_samples(controller, v0, w0, cap):
    """`LocalController._samples` before the cut (numpy's linspace, unique and meshgrid)."""
    limits, p = controller.limits, controller.params
    dv, dw = limits.max_accel * p.tick, limits.max_turn_accel * p.tick
    v_hi = min(cap, v0 + dv, limits.max_speed)
    v_lo = min(max(0.0, v0 - dv), v_hi)
    vs = np.unique(np.concatenate([np.linspace(v_lo, v_hi, p.v_samples), [0.0]]))
    w_lo = max(-limits.max_turn_rate, w0 - dw)
    w_hi = min(limits.max_turn_rate, w0 + dw)
    if w_lo > w_hi:
        w_lo = w_hi = np.copysign(limits.max_turn_rate, w0)
    ws = np.linspace(w_lo, w_hi, p.w_samples)
    if w_lo < 0.0 < w_hi:
        ws = np.unique(np.concatenate([ws, [0.0]]))
    grid_v, grid_w = np.meshgrid(vs, ws, indexing="ij")
    return np.column_stack([grid_v.ravel(), grid_w.ravel()])


def old_rollout(x, y, th, v0, w0, commands, times, limits):
    """`rollout` before the cut (the controller's only caller now rolls out the speed × turn
    rate grid): v and w ramp from (v0, w0) towards each command (s, 2) at the acceleration
    limits and then hold it (midpoint integration)."""
    commands = np.asarray(commands, dtype=float).reshape(-1, 2)
    times = np.asarray(times, dtype=float)
    edges = np.concatenate([[0.0], times])
    mids = 0.5 * (edges[1:] + edges[:-1])
    dts = np.diff(edges)
    dv = commands[:, 0:1] - v0
    dw = commands[:, 1:2] - w0
    v = v0 + np.clip(dv, -limits.max_accel * mids, limits.max_accel * mids)
    w = w0 + np.clip(dw, -limits.max_turn_accel * mids, limits.max_turn_accel * mids)
    dth = w * dts
    th_end = th + np.cumsum(dth, axis=1)
    th_mid = th_end - 0.5 * dth
    xs = x + np.cumsum(v * dts * np.cos(th_mid), axis=1)
    ys = y + np.cumsum(v * dts * np.sin(th_mid), axis=1)
    return np.stack([xs, ys, th_end], axis=-1)


def samples_and_rollout(v0, w0, cap):
    vs, ws = CONTROLLER._sample_speeds(v0, w0, cap)
    commands = np.column_stack([np.repeat(vs, len(ws)), np.tile(ws, len(vs))])
    return vs, ws, commands


def test_linspace_in_floats_is_numpys():
    rng = np.random.default_rng(14)
    cases = [(0.0, 0.0), (0.3, 0.3), (-1.5, 1.5), (0.0, 0.6), (1e-310, 2e-310), (-0.2, -0.2)]
    cases += [tuple(rng.uniform(-2.0, 2.0, 2)) for _ in range(300)]
    for start, stop in cases:
        for num in (2, 7, 15):
            assert np.array(_linspace(start, stop, num)).tobytes() == \
                np.linspace(start, stop, num).tobytes()


def test_the_sampled_commands_speeds_and_rollouts_are_as_before():
    rng = np.random.default_rng(15)
    limits = CONTROLLER.limits
    times = CONTROLLER._long_times
    cases = [(0.0, 0.0, 0.6), (0.6, 0.0, 0.0), (0.3, 3.0, 0.6), (0.3, -3.0, 0.2), (-0.1, 0.0, 0.6)]
    cases += [(float(rng.uniform(-0.1, 0.7)), float(rng.uniform(-2.0, 2.0)),
               float(rng.choice([0.0, 0.05, 0.3, 0.6, np.inf]))) for _ in range(60)]
    for v0, w0, cap in cases:
        vs, ws, commands = samples_and_rollout(v0, w0, cap)
        old = old_samples(CONTROLLER, v0, w0, cap)
        assert commands.tobytes() == old.tobytes()
        x, y, th = (float(v) for v in rng.uniform(-3.0, 3.0, 3))
        new = _rollout_grid(x, y, th, v0, w0, vs, ws, times, limits)
        assert new.tobytes() == old_rollout(x, y, th, v0, w0, old, times, limits).tobytes()
        speeds = np.repeat(_speeds(v0, vs[:, None], times, limits), len(ws), axis=0)
        assert speeds.tobytes() == _speeds(v0, old, times, limits).tobytes()


def test_a_shorter_stretch_of_the_path_ahead_is_the_first_samples_of_the_longest():
    """`_PathAhead` resamples once, to the farthest any piece looks: each piece's window and
    the room along it are what resampling to its own limit gave, round body and rectangle,
    paths longer and shorter than the limits, a path ending on a sample."""
    box = LocalController(COSTMAP, LIMITS, footprint=Footprint("rectangle", 0.3, 0.45, 0.39))
    rng = np.random.default_rng(16)
    paths = [np.array([[1.0, 1.0], [1.0, 1.0]]), np.array([[1.0, 1.0], [2.2, 1.0]]),
             np.array([[0.5, 0.5], [0.5, 0.5], [2.0, 0.5], [2.0, 2.5]])]
    paths += [np.cumsum(np.vstack([[1.5, 1.5], rng.normal(0.0, 0.3, (int(n), 2))]), axis=0)
              for n in rng.integers(1, 12, 40)]
    for controller in (CONTROLLER, box):
        for path in paths:
            stretch = _PathAhead(controller, path)
            for limit in (0.0, 0.3, 1.0, 1.45, 2.0, 2.2, 2.4, controller._farthest):
                window, along = _resample(path, 0.05, limit)
                mine, mine_along = stretch.window(limit)
                assert mine.tobytes() == window.tobytes()
                assert mine_along.tobytes() == along.tobytes()
                assert stretch.gaps(limit).tobytes() == controller._path_gaps(window).tobytes()
                if stretch.length > limit + 1e-9:      # the score's path run on past its end
                    run_on, _ = _resample(controller._run_on(path, limit), 0.05, limit)
                    assert run_on.tobytes() == window.tobytes()
