"""The behavior registry: macro-behaviors found by entry point (group `interbot.behaviors`).

A macro-behavior has one or more *realizations*, each a py_trees subtree factory with the
capabilities it needs; the first realization whose needs the robot meets is the one used
(FaceUser turns the pan-tilt head where there is one, else the whole body).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from importlib.metadata import entry_points
from typing import Any, Callable

import py_trees

from behaviors.exceptions import BehaviorError, UnknownBehaviorError, UnsupportedBehaviorError

GROUP = "interbot.behaviors"


@dataclass(frozen=True)
class Realization:
    name: str
    needs: frozenset[str]
    build: Callable[["BehaviorContext"], py_trees.behaviour.Behaviour]


@dataclass(frozen=True)
class BehaviorSpec:
    name: str
    description: str
    realizations: tuple[Realization, ...]
    parameters: dict[str, str] = field(default_factory=dict)   # dialog parameter → meaning

    @property
    def requires(self) -> frozenset[str]:
        """Capabilities every realization needs."""
        return frozenset.intersection(*(r.needs for r in self.realizations))

    @property
    def realization_needs(self) -> dict[str, frozenset[str]]:
        return {r.name: r.needs for r in self.realizations}

    def realization_for(self, capabilities: frozenset[str]) -> Realization:
        for realization in self.realizations:
            if realization.needs <= capabilities:
                return realization
        options = "; ".join(f"{r.name} needs {', '.join(sorted(r.needs))}" for r in self.realizations)
        raise UnsupportedBehaviorError(
            f"behavior '{self.name}' cannot run on a robot with {', '.join(sorted(capabilities))} "
            f"({options})")


@dataclass
class BehaviorContext:
    """What a subtree factory gets: the robot's skills (None when only drawing) and dialog params."""
    skills: Any
    params: dict[str, Any]

    def param(self, key: str, default: Any) -> Any:
        value = self.params.get(key)
        return default if value in (None, "", [], ()) else value


@cache
def behavior_specs() -> dict[str, BehaviorSpec]:
    """Every registered macro-behavior by name."""
    specs = {}
    for ep in entry_points(group=GROUP):
        try:
            spec = ep.load()
        except Exception as exc:
            raise BehaviorError(f"behavior plugin '{ep.name}' ({ep.value}) failed to load: {exc}") from exc
        if not isinstance(spec, BehaviorSpec):
            raise BehaviorError(f"behavior plugin '{ep.name}' ({ep.value}) is not a BehaviorSpec")
        specs[ep.name] = spec
    return specs


def get_behavior(name: str) -> BehaviorSpec:
    specs = behavior_specs()
    if name not in specs:
        raise UnknownBehaviorError(f"unknown behavior '{name}'; registered behaviors: "
                                   f"{', '.join(sorted(specs))}")
    return specs[name]
