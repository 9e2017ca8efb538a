"""Where the robot fits: goals for following and searching must keep the robot's radius plus
a margin from walls and shelves (the navigation skill's grid map); without a map every place
fits. A part of `Following` (`skills.following.follower`).
"""
from __future__ import annotations

import math

FREE_MARGIN = 0.1         # m beyond the robot's radius a goal must keep from walls


class Room:
    """Free places near a point, towards a point, on her trail (a part of `Following`)."""

    def _free(self, x: float, y: float) -> bool:
        """The robot fits at (x, y) with a margin (True without a map)."""
        nav = self.navigation
        if nav is None:
            return True
        margin = nav.profile.radius + FREE_MARGIN
        return bool(nav.grid.clearance(x, y) >= margin)

    def _free_towards(self, start, end):
        """The point nearest `end` on the segment from `start` where the robot fits, walking
        back from `end` (a prediction that runs into a shelf stops before it); None if none."""
        for k in range(10, -1, -1):
            f = k / 10
            x, y = start[0] + f * (end[0] - start[0]), start[1] + f * (end[1] - start[1])
            if self._free(x, y):
                return x, y
        return None

    def _nearest_free(self, x: float, y: float):
        """The nearest point within 0.6 m of (x, y) where the robot fits (a customer walking
        close along a shelf), or None."""
        for r in (0.1, 0.2, 0.3, 0.45, 0.6):
            for k in range(12):
                a = k * math.pi / 6
                if self._free(x + r * math.cos(a), y + r * math.sin(a)):
                    return x + r * math.cos(a), y + r * math.sin(a)
        return None

    def _on_trail(self, cx: float, cy: float):
        """A point of the customer's own trail about `distance` behind them where the robot
        fits: where the straight line from the robot would cut a shelf corner."""
        back = 0.0
        prev = (cx, cy)
        for x, y in reversed(self._trail):
            back += math.hypot(prev[0] - x, prev[1] - y)
            prev = (x, y)
            if back >= self.params.distance and self._free(x, y):
                return x, y
        return None
