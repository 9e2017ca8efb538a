"""Whether a person who leads the robot heeds it when it asks her to wait (issue 23): a trait
of each person, drawn from the scenario's distribution, as their yielding is
(`robots.sim.crowd`) and as passers-by's propensities are (`robots.sim.visitors`).

The simulated world learns what the robot said as visitors do: every utterance is in
`world.utterances`, and any of them counts but one asking people in the way to let the
robot pass (`robots.sim.understanding`: that is not for her). While a person leads the robot
(a `lead` step) and walks on, what the robot says from farther than `people.CALL_DISTANCE`
(nearer, it is talking to her face to face) and within `visitors.HEAR` (the range visitors
hear a call from) she takes as "wait for me"; farther away she does not hear it. How she
answers is her trait:

- ``never``: she walks on as before (she did not hear it over the store, or does not care);
- ``slow``: she walks at her slowed `pace` for `slow_for` s, then at her own pace again;
- ``wait``: she stands, facing the robot, until it is within WAITED m of her or her
  `patience` s have passed, then walks on at her own pace.

Each new ask she hears starts her answer afresh. A person who does not lead the robot
(shoppers, crossers, a customer walking out of the store) never heeds it.

The default distribution (`Distribution()`, used where a scenario states none) is a guess,
stated here and in docs/scenarios.md, not fitted to any benchmark: a quarter of people never
heed; of the others half slow down, half stop and wait; a slowed pace uniform in 0.4 .. 0.55
m/s (the stroll of a shopper, as the customers of bench_follow's other families walk: one the
robot can follow), kept 20 .. 60 s, then her own pace again; a patience
of 3 .. 10 s ("a few seconds"). A scenario sets its own in `[scenario] heeding = { never =
0.25, slow = 0.5, pace = [0.4, 0.55], slow_for = [20, 60], patience = [3, 10] }` and fixes one
person's answer with `heeding = "wait"` in their `[[person]]` (the numbers are still drawn).

Each person's trait is drawn from a generator of their own (the run's seed, their index and
HEED_STREAM), so drawing it changes no other random number of the run.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robots.sim.understanding import asks_to_pass

if TYPE_CHECKING:
    from robots.sim.people import SimPerson
    from robots.sim.world import World

ANSWERS = ("never", "slow", "wait")
WAITED = 2.0            # m: a waiting person walks on once the robot is this near
HEED_STREAM = 0x4EED    # seeds each person's heeding generator with the run's seed and index


@dataclass(frozen=True)
class Distribution:
    """Where people's heeding is drawn from (see the module's docstring for the default)."""
    never: float = 0.25                          # share who never heed
    slow: float = 0.5                            # of the others, share who slow down
    pace: tuple[float, float] = (0.4, 0.55)      # m/s, their slowed pace, uniform
    slow_for: tuple[float, float] = (20.0, 60.0)     # s they keep it, uniform
    patience: tuple[float, float] = (3.0, 10.0)      # s the others wait at most, uniform


@dataclass(frozen=True)
class Heed:
    """One person's answer to "wait for me": how, and its numbers."""
    how: str                 # one of ANSWERS
    pace: float              # m/s when slowing
    slow_for: float          # s
    patience: float          # s when waiting


def draw(distribution: Distribution, rng: np.random.Generator, how: str | None = None) -> Heed:
    """One person's heeding; `how` fixes the answer (the numbers are drawn all the same, so
    fixing it changes nothing else)."""
    u, v = float(rng.random()), float(rng.random())
    pace = float(rng.uniform(*distribution.pace))
    slow_for = float(rng.uniform(*distribution.slow_for))
    patience = float(rng.uniform(*distribution.patience))
    if how is None:
        how = "never" if u < distribution.never else "slow" if v < distribution.slow else "wait"
    if how not in ANSWERS:
        raise ValueError(f"heeding = {how!r} must be one of {', '.join(ANSWERS)}")
    return Heed(how, pace, slow_for, patience)


def draw_for(people: list["SimPerson"], distribution: Distribution, seed: int) -> None:
    """Give each person their heeding, from a generator of their own (seed, index)."""
    for index, person in enumerate(people):
        rng = np.random.default_rng([seed, index, HEED_STREAM])
        person.heeding = Listener(draw(distribution, rng, person.plan.heeding))


class Listener:
    """A person's heeding and what she is doing about the last ask she heard."""

    def __init__(self, heed: Heed) -> None:
        self.heed = heed
        self.heard = 0                     # asks heard (for tests and the benchmark)
        self.asked_at: float | None = None     # sim s of the last ask heard
        self._seen = 0                     # utterances of the world already listened to

    def start(self, world: "World") -> None:
        """She begins to lead: what the robot said before is not said to her now."""
        self._seen = len(world.utterances)

    def pace(self, person: "SimPerson", world: "World", in_earshot: bool) -> float | None:
        """The speed to lead at now: None her own, 0.0 stand (waiting for the robot).
        `in_earshot`: what the robot says now reaches her as a call (`robots.sim.people`)."""
        distance = math.hypot(world.body.x - person.x, world.body.y - person.y)
        said = [text for _, text in world.utterances[self._seen:] if not asks_to_pass(text)]
        self._seen = len(world.utterances)
        if said and in_earshot:
            self.heard += 1
            self.asked_at = world.t
        if self.asked_at is None:
            return None
        since = world.t - self.asked_at
        heed = self.heed
        if heed.how == "slow" and since < heed.slow_for:
            return min(heed.pace, person.plan.speed)
        if heed.how == "wait" and since < heed.patience and distance > WAITED:
            return 0.0
        if heed.how == "wait":
            self.asked_at = None           # waited: on at her own pace until asked again
        return None
