"""The percepts application conditions may read: declared with type, unit and range by plugins.

L3 never reads the blackboard: it reads a `PerceptView`, a read-only mapping from percept names
to values, built by L2 each tick. Percepts come from *providers*, registered by entry point in
the group `interbot.percepts` (the bundled ones in `behaviors/providers/`); a skill or behavior
package of one's own adds percepts the same way. The declarations let the application checker
reject an unknown name, a type, unit or value mismatch before the robot moves. A value of `None`
means *absent* (no user, stale data): a comparison with an absent value is false.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from typing import Any, Callable, Iterator

from behaviors.plugins import load_plugins

GROUP = "interbot.percepts"


@dataclass(frozen=True)
class PerceptSpec:
    name: str
    type: str                                  # "bool", "int", "float" or "str"
    unit: str | None = None                    # "m", "s", "rad" or None for a plain number
    range: tuple[float, float] | None = None   # inclusive; None when unbounded or unknown
    doc: str = ""
    values: tuple[str, ...] | None = None      # a str percept's possible values (None: any)
    provider: str = ""                         # the plugin that declares it


def spec(name: str, type_: str, unit: str | None = None,
         range_: tuple[float, float] | None = None, doc: str = "",
         values: tuple[str, ...] | None = None) -> PerceptSpec:
    return PerceptSpec(name, type_, unit, range_, doc, values)


@dataclass(frozen=True)
class PerceptProvider:
    """A plugin's percepts: their declarations and the function that reads them each tick.

    `read(ctx)` returns name -> value for (a subset of) `specs`; names it leaves out are absent.
    `needs` are the robot capabilities without which the percepts are always absent."""
    name: str
    specs: tuple[PerceptSpec, ...]
    read: Callable[["PerceptContext"], Mapping[str, Any]]
    needs: frozenset[str] = frozenset()


@dataclass
class PerceptContext:
    """What a provider reads from: the robot's skills, the time, and the moment the active
    macro-behavior started (the state's entry) with the users seen since then."""
    skills: Any
    now: float
    since: float
    users_seen: set
    stale_after: float
    behavior_status: str | None = None    # the active tree's last status: RUNNING/SUCCESS/…

    def fresh(self, key: str, default: Any = None) -> Any:
        """A blackboard value not older than `stale_after`, else `default` (stale = absent)."""
        return self.skills.blackboard.value(key, default, now=self.now, max_age=self.stale_after)


TIME_IN_STATE = PerceptSpec("time_in_state", "float", "s", (0.0, 1e9),
                            "seconds since the current state was entered (provided by L3)",
                            provider="runtime")


@dataclass(frozen=True)
class PerceptCatalog:
    providers: tuple[PerceptProvider, ...]
    specs: dict[str, PerceptSpec]
    problems: dict[str, str]               # plugin name -> why it did not load


@cache
def percept_catalog() -> PerceptCatalog:
    """Every percept provider by entry point; one that fails to load is reported, not fatal."""
    loaded, problems = load_plugins(GROUP, PerceptProvider, "percept")
    providers = list(loaded.values())
    specs: dict[str, PerceptSpec] = {}
    for provider in providers:
        for item in provider.specs:
            if item.name in specs:
                problems[provider.name] = (f"declares '{item.name}', already declared by "
                                           f"'{specs[item.name].provider}'")
                continue
            specs[item.name] = PerceptSpec(item.name, item.type, item.unit, item.range, item.doc,
                                           item.values, provider.name)
    return PerceptCatalog(tuple(providers), specs, problems)


def percept_specs() -> dict[str, PerceptSpec]:
    """Every declared percept by name (time_in_state excluded: L3 provides it)."""
    return dict(percept_catalog().specs)


class PerceptView(Mapping[str, Any]):
    """A read-only snapshot of percept values for one tick. `disabled` names the percepts whose
    plugin failed during the run: they read as absent, and a condition that reads one is off."""

    __slots__ = ("_values", "t", "disabled")

    def __init__(self, values: dict[str, Any], t: float,
                 disabled: frozenset[str] = frozenset()) -> None:
        self._values = dict(values)
        self.t = t
        self.disabled = disabled

    def with_values(self, extra: Mapping[str, Any]) -> "PerceptView":
        """The same snapshot with `extra` values added (L3 adds what it provides itself)."""
        return PerceptView({**self._values, **extra}, self.t, self.disabled)

    def __getitem__(self, name: str) -> Any:
        return self._values[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __repr__(self) -> str:
        return f"PerceptView(t={self.t:.2f}, {self._values!r})"
