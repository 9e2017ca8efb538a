"""What the tracker tells the rest of the robot about one person: a snapshot per tick."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TENTATIVE = "tentative"   # seen a few times; may still be a false positive
CONFIRMED = "confirmed"   # seen often enough to be believed, and seen recently
LOST = "lost"             # believed, but not seen for a while (occluded, out of view); coasting


@dataclass
class Track:
    """One tracked person in the world frame (metres, seconds).

    `cov` is the 2x2 position covariance, so consumers can judge how sure the position is
    (it grows while a track coasts). `id` never changes for the life of the track.
    """
    id: int
    x: float
    y: float
    vx: float
    vy: float
    cov: np.ndarray
    status: str
    born: float               # time of the first detection
    confirmed_at: float | None
    last_seen: float          # time of the newest detection assigned to it
    # what the person looked like in the newest camera detection assigned to it (a colour
    # histogram, robots.devices.Detection.appearance) and when; None without a camera
    appearance: tuple[float, ...] | None = None
    appearance_t: float | None = None
    # when a detection from a source that may confirm a person (the camera; every source on a
    # robot without one) was last assigned to it: laser legs alone (a cart's wheels, a chair)
    # keep a track alive but say less about who it is
    confirmed_seen: float | None = None

    @property
    def speed(self) -> float:
        return float(np.hypot(self.vx, self.vy))

    @property
    def believed(self) -> bool:
        """Confirmed or lost: a real person, whether or not seen in this very frame."""
        return self.status != TENTATIVE
