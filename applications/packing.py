"""Laser readings stored so that they compress, without changing a bit of them.

Replay needs each laser reading bit for bit (a simulated laser adds fresh noise to every read),
so the recording keeps them as float64 — base64 of 8 little-endian bytes per range. zstd
compresses those poorly: the low mantissa bytes are noise. Stored byte plane by byte plane
instead (every range's byte 0, then every range's byte 1, …), the sign, exponent and high
mantissa bytes, nearly alike from one range to the next, form long runs that zstd shrinks, and
the recording's largest part shrinks by about a fifth. `unpack_inputs(pack_inputs(x)) == x`.

In a recording, a reading's `ranges` (or `angles`) then appears as `ranges@planes`.
"""
from __future__ import annotations

import base64
from typing import Any

import numpy as np

FIELDS = ("ranges", "angles")          # float64 arrays as base64, in robots' tap format
SUFFIX = "@planes"
WIDTH = 8                              # bytes per float64


def to_planes(text: str) -> str:
    """base64 of float64 values → base64 of the same bytes, plane by plane."""
    raw = np.frombuffer(base64.b64decode(text), dtype=np.uint8)
    return base64.b64encode(raw.reshape(-1, WIDTH).T.tobytes()).decode("ascii")


def from_planes(text: str) -> str:
    """The inverse of `to_planes`."""
    raw = np.frombuffer(base64.b64decode(text), dtype=np.uint8)
    return base64.b64encode(raw.reshape(WIDTH, -1).T.tobytes()).decode("ascii")


def pack_inputs(inputs: list) -> list:
    """A tick's [key, value] readings with every float64 array plane by plane (a new list;
    the snapshot's own is left as it is)."""
    out = []
    for entry in inputs:
        key, value = entry
        out.append([key, _pack(value)] if type(value) is dict and _has_array(value) else entry)
    return out


def unpack_inputs(inputs: list) -> list:
    """A recorded tick's readings as the robot read them (packed or not)."""
    out = []
    for key, value in inputs:
        if type(value) is dict and any(name + SUFFIX in value for name in FIELDS):
            value = {(name[:-len(SUFFIX)] if name.endswith(SUFFIX) else name):
                     (from_planes(item) if name.endswith(SUFFIX) else item)
                     for name, item in value.items()}
        out.append([key, value])
    return out


def _has_array(value: dict) -> bool:
    return any(type(value.get(name)) is str for name in FIELDS)


def _pack(value: dict[str, Any]) -> dict[str, Any]:
    return {(name + SUFFIX if name in FIELDS and type(item) is str else name):
            (to_planes(item) if name in FIELDS and type(item) is str else item)
            for name, item in value.items()}
