"""Asking a customer who walks faster than the robot to wait (issue 23: "a customer faster
than the robot is kept up with where possible and searched for where not").

A person following somebody who walks off too fast for them says so. The robot does the same
(its words are captioned on the touch screen too, `skills.speech`):

- **falling behind**: she is seen, more than BEHIND m beyond the setpoint, walking at least
  as fast as the robot may drive now (so no speed of its own closes the gap: its top speed,
  or the near-people cap while other people are near it, `Motion.top_speed`) now and as she
  usually walks (the follower's running average of her pace: a shopper catching up after
  being held up is not a fast walker), and the gap has grown by GROWING m or more over the
  last WINDOW s: it asks ASK. Then not again for
  ASK_AGAIN s, however far behind it stays (it does not nag);
- **lost her**: her track has been lost for LOST_AFTER s (not a flicker of the tracker),
  within RECENT s of her outpacing it: it says LOST as soon as it may, once per loss (the
  search's own call, "Where are you?", comes only after `search_after`).

Any two of these are QUIET s apart at least. A customer who walks no faster than the robot
may drive is never asked (the robot can close that gap; a blocked way, a search that left it
behind, are not hers to wait for). Among shoppers the robot may drive no faster than the
near-people cap (0.3 m/s on PERSES) while she strolls on at 0.5: it fell 3 m behind her in
15 s and lost her for good without a word (crowd10 seed 0, issue 23). `PaceWatch` decides;
the follower says the words (`skills.following.follower`).
"""
from __future__ import annotations

import math
from collections import deque

ASK = "Please wait for me, I cannot walk as fast as you."
LOST = "Please wait, I lost you."
BEHIND = 1.0        # m beyond the setpoint before the robot counts as falling behind
GROWING = 0.3       # m the gap must have grown by ...
WINDOW = 1.5        # s ... over this long (she pulls away at 0.2 m/s or more)
FASTER = 1.0        # her pace at least this times the robot's top speed: it cannot close up
ASK_AGAIN = 15.0    # s before the robot asks again while it stays behind
RECENT = 5.0        # s: a loss this soon after she outpaced the robot is said ...
LOST_AFTER = 1.0    # s: ... once it has lasted this long
QUIET = 4.0         # s between any two of the robot's asks (ASK takes 3 s to say)


class PaceWatch:
    """Watches the gap to the customer; says when to ask her to wait (see the module)."""

    def __init__(self) -> None:
        self._gaps: deque[tuple[float, float]] = deque()   # (t, m beyond the setpoint)
        self._asked = -math.inf        # when ASK was said last
        self._said = -math.inf         # when either was said last
        self._outpaced = -math.inf     # when she was last seen pulling away too fast
        self._lost_said = False        # LOST said in this loss
        self._lost_since: float | None = None

    def seen(self, now: float, gap: float, pace: float, top_speed: float) -> str | None:
        """She is seen `gap` m beyond the setpoint walking at `pace` m/s (the smaller of her
        pace now and her usual one); the words to ask her with now, or None."""
        self._lost_said = False
        self._lost_since = None
        self._gaps.append((now, gap))
        while self._gaps and now - self._gaps[0][0] > WINDOW + 1e-6:
            self._gaps.popleft()
        first_t, first_gap = self._gaps[0]
        growing = now - first_t >= WINDOW * 0.75 and gap - first_gap >= GROWING
        if not (growing and pace >= FASTER * top_speed):
            return None
        self._outpaced = now
        if gap < BEHIND or now - self._asked < ASK_AGAIN or now - self._said < QUIET:
            return None
        self._asked = self._said = now
        return ASK

    def lost(self, now: float) -> str | None:
        """Her track is lost (every tick of the loss); the words to say now, or None."""
        self._gaps.clear()
        if self._lost_since is None:
            self._lost_since = now
        if (self._lost_said or now - self._lost_since < LOST_AFTER - 1e-6
                or now - self._outpaced > RECENT
                or now - self._said < QUIET):
            return None
        self._lost_said = True
        self._said = now
        return LOST
