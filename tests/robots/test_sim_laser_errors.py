"""The simulated laser's error model: the bundled floors keep the plain noise (same random
numbers as before), a map_server map gets range noise of a few cm, drop-outs and stray short
returns (issue 22, point 4)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from robots.profile import load_profile
from robots.sim.floor import load_floor
from robots.sim.laser_errors import MAP_DROPOUT, MAP_NOISE, MAP_SPURIOUS, LaserErrors


def test_a_bundled_floor_keeps_the_profiles_plain_noise_and_its_random_numbers():
    laser = load_profile("horos").laser
    errors = LaserErrors.for_floor(laser, load_floor("office"))
    assert errors == LaserErrors(laser.noise)
    ranges = np.linspace(0.5, 7.5, 181)
    plain = np.maximum(ranges + np.random.default_rng(3).normal(0.0, laser.noise, 181), 0.0)
    assert np.array_equal(errors.apply(ranges, np.random.default_rng(3)), plain)


def test_a_map_server_map_gets_noise_drop_outs_and_short_returns(tmp_path):
    from tests.skills.test_navigation_doors import write_door_map
    floor = load_floor(Path(write_door_map(tmp_path, 0.8)))
    errors = LaserErrors.for_floor(load_profile("horos").laser, floor)
    assert errors == LaserErrors(MAP_NOISE, MAP_DROPOUT, MAP_SPURIOUS)
    ranges = np.full(200_000, 4.0)
    out = errors.apply(ranges, np.random.default_rng(0))
    lost = np.isinf(out)
    short = out < 4.0 - 5 * MAP_NOISE
    assert abs(lost.mean() - MAP_DROPOUT) < 0.002
    assert abs(short.mean() - MAP_SPURIOUS) < 0.001
    assert (out[short] > 0.0).all()
    normal = out[~lost & ~short]
    assert abs(normal.std() - MAP_NOISE) < 0.001 and abs(normal.mean() - 4.0) < 0.001
