"""What a real laser scanner gets wrong, for the simulated one.

A scan of the simulator's ray caster is exact; a SICK or Hokuyo scan is not. Besides Gaussian
range noise (the datasheets give a few centimetres of systematic plus statistical error
indoors), some beams return nothing (a dark, shiny or glancing surface: a "max-range" reading)
and some return short of the wall (dust, an edge hit by part of the spot, a mixed pixel). The
beams' count, field of view and range come from the profile's [laser] table.

The bundled floors keep the profile's plain noise (their recorded runs replay unchanged); a
floor made from a map_server map, a building the robot has never been tuned for, gets the
realistic model (`for_floor`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MAP_NOISE = 0.02            # m: range noise (1 sigma) on a user's map
MAP_DROPOUT = 0.02          # share of beams without an echo
MAP_SPURIOUS = 0.003        # share of beams returning short of what they hit (dust, a mixed pixel)
NEAREST_RETURN = 0.05       # m: a spurious return lies between this and the true range


@dataclass(frozen=True)
class LaserErrors:
    noise: float                 # m, Gaussian range noise (1 sigma)
    dropout: float = 0.0         # share of beams with no echo (returned as inf)
    spurious: float = 0.0        # share of beams with a return uniform in (NEAREST_RETURN, range)

    @classmethod
    def for_floor(cls, laser, floor) -> "LaserErrors":
        """The profile's noise alone on a bundled floor; the realistic model on a floor made
        from a map_server map (`floor.source` set)."""
        if getattr(floor, "source", None) is None:
            return cls(laser.noise)
        return cls(max(laser.noise, MAP_NOISE), MAP_DROPOUT, MAP_SPURIOUS)

    def apply(self, ranges: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """`ranges` (inf: no echo) as the scanner would report them. With only noise, the
        random numbers drawn are exactly those of the plain model."""
        out = ranges
        if self.noise > 0:
            out = np.maximum(out + rng.normal(0.0, self.noise, out.shape), 0.0)
        if self.dropout <= 0 and self.spurious <= 0:
            return out
        draw = rng.random(out.shape)
        short = draw < self.spurious
        lost = (draw >= self.spurious) & (draw < self.spurious + self.dropout)
        out = out.copy()
        echo = np.isfinite(out)
        reach = np.where(echo, out, NEAREST_RETURN * 20)
        fraction = rng.random(out.shape)
        out[short] = NEAREST_RETURN + fraction[short] * np.maximum(reach[short] - NEAREST_RETURN,
                                                                   0.0)
        out[lost] = np.inf
        return out
