"""Who is the interaction partner: the believed person who is near and coming closer.

Each believed track gets a score, its distance minus a bonus for approaching; the lowest score
wins. The current user keeps the role until someone else scores better by `hysteresis` metres
for `switch_time` seconds, so two people at similar distances do not make the choice flip.
"""
from __future__ import annotations

import math

from skills.people.track import CONFIRMED, LOST, Track


def distance(track: Track, robot_xy: tuple[float, float]) -> float:
    """Metres from the robot's centre to the person."""
    return math.hypot(track.x - robot_xy[0], track.y - robot_xy[1])


def approach_speed(track: Track, robot_xy: tuple[float, float]) -> float:
    """The person's own speed towards the robot's position (m/s; negative when leaving).

    Only the person's velocity counts, so a robot driving up to someone does not make that
    person 'approaching'."""
    dx, dy = robot_xy[0] - track.x, robot_xy[1] - track.y
    d = math.hypot(dx, dy)
    if d < 1e-9:
        return 0.0
    return (track.vx * dx + track.vy * dy) / d


class UserSelector:
    """Keeps the choice of the user across ticks; `select` once per tick."""

    def __init__(self, max_range: float = 5.0, hysteresis: float = 0.5,
                 switch_time: float = 0.5, approach_weight: float = 1.0) -> None:
        self.max_range = max_range              # m; people farther away are not candidates
        self.hysteresis = hysteresis            # m of score a challenger must win by
        self.switch_time = switch_time          # s the challenger must keep winning
        self.approach_weight = approach_weight  # s; 1 m/s towards the robot counts as 1 m nearer
        self.user_id: int | None = None
        self._challenger: tuple[int, float] | None = None   # (id, since when it is better)

    def score(self, track: Track, robot_xy: tuple[float, float]) -> float:
        """Lower is a better user: distance, less a bonus for walking towards the robot."""
        bonus = self.approach_weight * max(0.0, approach_speed(track, robot_xy))
        return distance(track, robot_xy) - bonus

    def reset(self) -> None:
        """Forget the user (e.g. when an interaction ends)."""
        self.user_id = None
        self._challenger = None

    def select(self, tracks: list[Track], robot_xy: tuple[float, float], t: float) -> Track | None:
        """The user among `tracks` at time `t`, or None when nobody qualifies."""
        current = self._current(tracks, robot_xy)
        candidates = [tr for tr in tracks if tr.status == CONFIRMED
                      and distance(tr, robot_xy) <= self.max_range]
        best = min(candidates, key=lambda tr: self.score(tr, robot_xy), default=None)
        if current is None:
            self._challenger = None
            self.user_id = best.id if best is not None else None
            return best
        if best is None or best.id == current.id or (
                self.score(best, robot_xy) > self.score(current, robot_xy) - self.hysteresis):
            self._challenger = None
            return current
        if self._challenger is None or self._challenger[0] != best.id:
            self._challenger = (best.id, t)
        if t - self._challenger[1] >= self.switch_time:
            self.user_id, self._challenger = best.id, None
            return best
        return current

    def _current(self, tracks: list[Track], robot_xy: tuple[float, float]) -> Track | None:
        """The previous user while still tracked (a lost, i.e. briefly hidden, user stays) and
        within range plus the hysteresis margin."""
        for tr in tracks:
            if tr.id == self.user_id and tr.status in (CONFIRMED, LOST):
                if distance(tr, robot_xy) <= self.max_range + self.hysteresis:
                    return tr
        return None
