"""Searching: what the robot does while the customer is unseen.

- **hidden**: the robot keeps going towards where her Kalman state predicts her, stopping
  `distance` short of it.
- **searching**: hidden for `search_after` s: the robot drives to within `distance` of the
  predicted place, turns round there, then once more 3 m on along her trail, and calls out
  every `call_every` s. (Giving up after `give_up_after` s is the phase machine's.)

A part of `Following` (`skills.following.follower`); it reads `params`, `navigation`,
`speech`, the belief and her trail (`skills.following.identity`) and where the robot fits
(`skills.following.room`).
"""
from __future__ import annotations

import math
from dataclasses import replace

from skills.motion import Goal
from skills.status import Status

SEARCH_AHEAD = 3.0        # m beyond the last seen place, along her trail, searched second


class Searching:
    """Approaching the prediction, searching round it and ahead (a part of `Following`)."""

    def _approach_prediction(self, predicted, robot, now: float) -> None:
        """Keep going to where the customer should be, stopping `distance` short of it."""
        p = self.params
        dx, dy = predicted[0] - robot[0], predicted[1] - robot[1]
        d = math.hypot(dx, dy)
        if d <= p.distance + 0.1:
            self._face(predicted[0], predicted[1], robot, now)
            return
        goal = (predicted[0] - dx / d * p.distance, predicted[1] - dy / d * p.distance)
        if not self._free(*goal):
            goal = predicted
        self._drive_to(goal, self._belief.speed + p.speed_gain * (d - p.distance), now)

    def _search(self, predicted, robot, now: float) -> None:
        """Drive to within `distance` of the predicted place; there, turn round in thirds; call
        out now and then."""
        p = self.params
        if self.speech is not None and now - self._last_call >= p.call_every:
            self._last_call = now
            self.speech.say(p.call, now)
            self.state = replace(self.state, calls=self.state.calls + 1)
        goal = self._search_goal or predicted
        d = math.hypot(goal[0] - robot[0], goal[1] - robot[1])
        nav = self.navigation
        # navigation's outcome counts only for this goal, not for the approach while hidden
        # (which stops `distance` short of the prediction, out of sight round a shelf end)
        ours = self._goal is not None and math.hypot(self._goal[0] - goal[0],
                                                     self._goal[1] - goal[1]) <= p.goal_step
        # within `distance` of the place it can see it, and she may be standing right there
        arrived = nav is None or d < p.distance or (ours and nav.status.status in (
            Status.SUCCEEDED, Status.FAILED))
        if nav is not None and ours and nav.status.failed and self._trail:
            # the predicted place cannot be reached: search from the last place on the trail
            fallback = next((pt for pt in reversed(self._trail) if self._free(*pt)), None)
            if fallback is not None and fallback != self._search_goal:
                self._search_goal = fallback
                self._goal = None
                arrived = False
        goal = self._search_goal or predicted
        if not arrived:
            self._drive_to(goal, 0.4, now)
            return
        if self._search_heading is None or abs(_wrap(self._search_heading - robot[2])) < 0.15:
            if self._search_turns >= 3 and self._search_further(goal):
                return                  # looked all round here: on to where she was heading
            self._search_heading = _wrap(robot[2] + 2 * math.pi / 3)
            self._search_turns += 1
        self._hold(now)
        self.motion.start(Goal("turn_to", bearing=self._search_heading), now)

    def _search_further(self, here) -> bool:
        """After a full turn at the predicted place, search SEARCH_AHEAD further along the
        direction her trail last took (she went on round a shelf end, out of sight from the
        corner): once. True if there is such a place."""
        if self._searched_ahead or len(self._trail) < 2:
            return False
        self._searched_ahead = True
        (x0, y0), (x1, y1) = self._trail[max(0, len(self._trail) - 4)], self._trail[-1]
        step = math.hypot(x1 - x0, y1 - y0)
        if step < 0.2:
            return False
        ahead = (x1 + (x1 - x0) / step * SEARCH_AHEAD, y1 + (y1 - y0) / step * SEARCH_AHEAD)
        # where the robot fits: near that point (she walked close along a shelf), else short of it
        goal = self._nearest_free(*ahead) or self._free_towards((x1, y1), ahead)
        if goal is None or math.hypot(goal[0] - here[0], goal[1] - here[1]) < 1.0:
            return False
        self._search_goal, self._goal = goal, None
        self._search_turns, self._search_heading = 0, None
        return True


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))
