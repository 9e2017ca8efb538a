"""Builds the read-only percept view L3 conditions read, from every percept provider.

Stale entries count as absent. `people.new` and `user.left` are relative to the moment the
active macro-behavior started, i.e. to when the current state was entered. A provider whose
`needs` the robot lacks contributes nothing (its percepts read as absent).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

from behaviors.percepts import PerceptContext, PerceptView, percept_catalog

log = logging.getLogger("interbot.percepts")

STALE_AFTER = 0.5          # s: older blackboard entries are treated as absent


# The blackboard entry each percept is computed from, for its age (inspector, recordings).
SOURCES = {
    "people.count": "people/tracks", "people.new": "people/tracks",
    "user.present": "people/user", "user.distance": "people/user_distance",
    "user.approaching": "people/user_approach", "user.left": "people/tracks",
    "survey.done": "survey/progress", "survey.answered": "survey/progress",
    "speech.busy": "speech/busy", "motion.failed": "skills/motion/status",
    "robot.fault": "robot/link",
}


FRESH_ONLY = frozenset({"people/tracks", "people/user", "people/user_distance",
                        "people/user_approach", "speech/busy", "robot/link"})


def describe(view: PerceptView, ages: dict[str, float]) -> dict[str, dict]:
    """Each percept's value, the age (s) of the blackboard entry it comes from (`ages`, by key)
    and whether it is stale: older than STALE_AFTER where that makes it read as absent; a
    percept whose plugin failed is marked `disabled`."""
    out = {}
    for name, value in view.items():
        source = SOURCES.get(name)
        age = ages.get(source)
        stale = age is None or (source in FRESH_ONLY and age > STALE_AFTER)
        out[name] = {"value": value, "age": age, "stale": stale}
        if name in view.disabled:             # its plugin failed during the run
            out[name]["disabled"] = True
    return out


@dataclass(frozen=True)
class PluginFailure:
    """A percept plugin that raised while reading: it is off for the rest of the run."""
    plugin: str
    error: str                   # "ValueError: …"
    percepts: tuple[str, ...]    # what it declares, now disabled


class PerceptTracker:
    """Remembers what "since the state was entered" needs: the start time and the users seen;
    and which percept plugins failed (a plugin that raises once stays off: nothing that
    failed resumes by itself)."""

    def __init__(self) -> None:
        self.since = 0.0
        self.users_seen: set[int] = set()
        self.failed: dict[str, PluginFailure] = {}
        self.disabled: frozenset[str] = frozenset()
        self._unreported: list[PluginFailure] = []

    def new_failures(self) -> list[PluginFailure]:
        """The failures since the last call (each is reported once)."""
        found, self._unreported = self._unreported, []
        return found

    def restart(self, now: float) -> None:
        self.since = now
        self.users_seen = set()

    def view(self, skills, now: float, behavior_status: str | None = None) -> PerceptView:
        ctx = PerceptContext(skills, now, self.since, self.users_seen, STALE_AFTER,
                             behavior_status)
        values = {}
        capabilities = skills.capabilities
        for provider in percept_catalog().providers:
            names = {s.name for s in provider.specs}
            if provider.needs <= capabilities and provider.name not in self.failed:
                read = self._read(provider, ctx)
                values.update(read)
                names -= set(read)
            values.update(dict.fromkeys(names))
        return PerceptView(values, now, self.disabled)

    def _read(self, provider, ctx: PerceptContext) -> dict:
        """The provider's values; a provider that raises (or returns no mapping) is disabled
        with its percepts, and the rest of the percepts are still read."""
        try:
            return dict(provider.read(ctx))
        except Exception as exc:   # a broken plugin disables only itself
            failure = PluginFailure(provider.name, f"{type(exc).__name__}: {exc}",
                                    tuple(sorted(s.name for s in provider.specs)))
            log.info("percept plugin '%s' raised %s; its percepts are off: %s",
                      provider.name, failure.error, ", ".join(failure.percepts))
            self.failed[provider.name] = failure
            self.disabled = self.disabled | frozenset(failure.percepts)
            self._unreported.append(failure)
            return {}
