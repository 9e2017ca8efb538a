"""Laser arrays stored plane by plane: exactly the same readings back, in fewer bytes."""
from __future__ import annotations

import base64

import numpy as np
import zstandard
from hypothesis import given
from hypothesis import strategies as st

from applications.packing import SUFFIX, pack_inputs, unpack_inputs


def tap(values) -> str:
    """An array as robots' tap writes it: float64, little-endian, base64."""
    return base64.b64encode(np.asarray(values, dtype="<f8").tobytes()).decode("ascii")


floats = st.floats(allow_nan=True, allow_infinity=True, width=64)


@given(st.lists(floats, max_size=400), st.one_of(st.none(), st.lists(floats, max_size=50)))
def test_packing_gives_back_every_bit(ranges, angles):
    reading = {"t": 1.5, "angles": None if angles is None else tap(angles),
               "ranges": tap(ranges), "origin": [0.16, 0.0, 0.0]}
    inputs = [["now", 1.5], ["laser.read", reading], ["base.read_state", {"x": 1.0}]]
    packed = pack_inputs(inputs)
    assert "ranges" not in packed[1][1] and "ranges" + SUFFIX in packed[1][1]
    assert inputs[1][1]["ranges"] == reading["ranges"]          # the snapshot is not changed
    assert unpack_inputs(packed) == inputs


def test_readings_without_arrays_and_old_recordings_pass_as_they_are():
    inputs = [["now", 2.0], ["detector.detect", [{"x": 1.0}]], ["laser.read", {"ranges": None}]]
    assert pack_inputs(inputs) == inputs
    old = [["laser.read", {"t": 1.0, "ranges": tap([1.0, 2.0])}]]
    assert unpack_inputs(old) == old


def test_noisy_ranges_compress_by_at_least_a_tenth_more_plane_by_plane():
    rng = np.random.default_rng(7)
    truth = 1.0 + 4.0 * np.abs(np.sin(np.linspace(0, 3, 181)))
    reads = [["laser.read", {"ranges": tap(truth + rng.normal(0, 0.01, 181))}]
             for _ in range(300)]
    plain = zstandard.compress(str(reads).encode(), 3)
    planes = zstandard.compress(str(pack_inputs(reads)).encode(), 3)
    assert len(planes) < 0.9 * len(plain)
