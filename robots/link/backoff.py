"""The reconnect policy: wait longer after each failed attempt, up to a ceiling.

Why: a driver that lost its robot must keep trying (the cable may come back) without flooding
the port or the log; exponential back-off with a cap is the usual answer. Pure and
deterministic (optional jitter comes from a seeded generator), so tests can check the delays.
"""
from __future__ import annotations

import random
from dataclasses import dataclass, field


@dataclass
class Backoff:
    initial: float = 0.1      # s, delay before the first retry
    factor: float = 2.0
    maximum: float = 2.0      # s, ceiling
    jitter: float = 0.0       # fraction of each delay added at random (0 = none)
    seed: int = 0
    attempts: int = field(default=0, init=False)

    def __post_init__(self) -> None:
        if self.initial < 0 or self.factor < 1 or self.maximum < self.initial:
            raise ValueError(f"bad back-off {self.initial=} {self.factor=} {self.maximum=}")
        self._rng = random.Random(self.seed)

    def next_delay(self) -> float:
        """The delay before the next attempt; each call counts one more failed attempt."""
        delay = min(self.maximum, self.initial * self.factor ** self.attempts)
        self.attempts += 1
        if self.jitter:
            delay += delay * self.jitter * self._rng.random()
        return delay

    def reset(self) -> None:
        """Call after a success: the next failure starts again from `initial`."""
        self.attempts = 0
