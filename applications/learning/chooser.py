"""The run-time side of choice points: on entering a state with a `<choice>`, pick an
alternative; from then on watch the choice's success condition each tick; when it holds the
episode is a success, when `within` has passed (or the same choice is made again) a failure.
Each choice and each outcome is an event (`choice`, `outcome`) for the trace and the recording,
and each outcome is written to the store as it happens.

The strategies: `first` (always the first alternative), `random` (uniform), `rotate` (in turn,
carrying on from the stored trials after a restart) and `learn` (a bandit per choice point and
context, `applications.learning.bandit`). A run may force one strategy on every choice point
(`--choose`, for comparing them in a campaign) and freeze learning (exploit only).
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from applications.alternatives import STATE_PERCEPT, Alternative, ChoicePoint
from applications.learning import bandit
from applications.learning.store import Episode, LearningStore, Settings

INT_CONTEXT_CAP = 3          # int context values from this one up are one situation ("3+")
NO_CONTEXT = ""


@dataclass(frozen=True)
class LearnerOptions:
    method: str = "thompson"          # the bandit: thompson or ucb
    strategy: str | None = None       # force this `by` on every choice point (None: the file's)
    frozen: bool = False              # exploit only, on every choice point
    window: int | None = None         # count only the newest episodes (None: the store's setting)
    seed: int = 0


@dataclass
class _Open:
    point: ChoicePoint
    alternative: Alternative
    context: str
    chosen_by: str
    since: float


def context_key(names: tuple[str, ...], percepts: Mapping[str, Any]) -> str:
    """The situation a choice is made in, as the store keys it: `people.count=2,…`."""
    parts = []
    for name in names:
        value = percepts.get(name)
        if value is None:
            text = "absent"
        elif isinstance(value, bool):
            text = "true" if value else "false"
        elif isinstance(value, int):
            text = f"{INT_CONTEXT_CAP}+" if value >= INT_CONTEXT_CAP else str(value)
        else:
            text = str(value)
        parts.append(f"{name}={text}")
    return ",".join(parts) or NO_CONTEXT


class Chooser:
    """Chooses at the choice points of one run and keeps their open episodes."""

    def __init__(self, points: tuple[ChoicePoint, ...], store: LearningStore | None,
                 options: LearnerOptions = LearnerOptions(),
                 emit: Callable[[dict[str, Any]], None] = lambda event: None,
                 run_id: str = "") -> None:
        self.points = points
        self.store = store
        self.options = options
        self.emit = emit
        self.run_id = run_id
        self.rng = np.random.default_rng(options.seed)
        self.open: dict[str, _Open] = {}
        self._turns: dict[str, int] = {}

    def pick(self, state: str, percepts: Mapping[str, Any], now: float) -> Alternative | None:
        """The alternative for entering `state`, or None when no choice point applies."""
        point = next((p for p in self.points if p.applies(state, percepts)), None)
        if point is None:
            return None
        if point.id in self.open:              # chosen again before the last one succeeded
            self._finish(self.open[point.id], False, now)
        context = context_key(point.context, percepts)
        by = self.options.strategy or point.by
        index = self._choose(point, by, context)
        alternative = point.alternatives[index]
        self.emit({"t": round(now, 3), "kind": "choice", "point": point.id, "state": state,
                   "alternative": alternative.id, "behavior": alternative.behavior, "by": by,
                   "context": context})
        if point.success is not None:
            self.open[point.id] = _Open(point, alternative, context, by, now)
        return alternative

    def watch(self, state: str, percepts: Mapping[str, Any], now: float) -> None:
        """Once per tick: end the open episodes whose success holds or whose time is up."""
        if not self.open:
            return
        values = None
        for episode in list(self.open.values()):
            success = episode.point.success
            elapsed = now - episode.since
            if values is None:
                values = {**percepts, STATE_PERCEPT: state}
            if success.condition.evaluate(values, elapsed):
                self._finish(episode, True, now)
            elif elapsed >= success.within - 1e-9:
                self._finish(episode, False, now)

    def close(self, now: float) -> None:
        """The run ends: an episode still open has no outcome yet and is not counted."""
        for episode in list(self.open.values()):
            self.emit({"t": round(now, 3), "kind": "outcome", "point": episode.point.id,
                       "alternative": episode.alternative.id, "success": None,
                       "after": round(now - episode.since, 3), "context": episode.context,
                       "by": episode.chosen_by, "note": "the run ended first; not counted"})
        self.open.clear()

    # -- choosing --------------------------------------------------------------------------

    def _choose(self, point: ChoicePoint, by: str, context: str) -> int:
        count = len(point.alternatives)
        if by == "first":
            return 0
        if by == "random":
            return int(self.rng.integers(count))
        if by == "rotate":
            turn = self._turns.get(point.id)
            if turn is None:
                stored = self.store.counts(point.id) if self.store is not None else {}
                turn = sum(n for _, n in stored.values())
            self._turns[point.id] = turn + 1
            return turn % count
        settings = self.store.settings(point.id) if self.store is not None else Settings()
        window = settings.window if self.options.window is None else self.options.window
        counts = self.store.counts(point.id, context, window) if self.store is not None else {}
        successes = [counts.get(a.id, (0, 0))[0] for a in point.alternatives]
        trials = [counts.get(a.id, (0, 0))[1] for a in point.alternatives]
        return bandit.choose(successes, trials, self.rng, self.options.method,
                             frozen=settings.frozen or self.options.frozen,
                             min_share=settings.min_share)

    def _finish(self, episode: _Open, success: bool, now: float) -> None:
        del self.open[episode.point.id]
        after = now - episode.since
        self.emit({"t": round(now, 3), "kind": "outcome", "point": episode.point.id,
                   "alternative": episode.alternative.id, "success": success,
                   "after": round(after, 3), "context": episode.context,
                   "by": episode.chosen_by})
        if self.store is not None:
            self.store.record(Episode(episode.point.id, episode.context, episode.alternative.id,
                                      episode.chosen_by, success, after, now, self.run_id))
