"""The controller's CPU cuts change no bit: its rewritten kernels against the code they
replaced (kept here verbatim), on poses inside, at the edge of and off the map."""
from __future__ import annotations

import numpy as np

from skills.navigation.controller import _arc, _project, _resample
from tests.skills.test_navigation_controller import CONTROLLER, ROOM


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


def test_map_clearance_keeps_the_shape_of_a_single_point_and_a_row():
    for x, y in [(1.0, 1.0), (np.array([1.0]), np.array([1.0])), (-3.0, 1.0),
                 (np.array([0.4, 1.3, -2.0]), np.array([[0.7], [1.1]]))]:
        new, old = CONTROLLER._map_clearance(x, y), old_map_clearance(CONTROLLER, x, y)
        assert new.shape == old.shape
        assert new.tobytes() == old.tobytes()
