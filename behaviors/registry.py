"""The behavior registry: macro-behaviors found by entry point (group `interbot.behaviors`).

A macro-behavior has one or more *realizations*, each a py_trees subtree factory with the
capabilities it needs; the first realization whose needs the robot meets is the one used
(FaceUser turns the pan-tilt head where there is one, else the whole body).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from typing import Any, Callable

import py_trees

from behaviors.exceptions import UnknownBehaviorError, UnsupportedBehaviorError
from behaviors.parameters import ParameterSpec
from behaviors.plugins import load_plugins

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
    parameters: dict[str, ParameterSpec] = field(default_factory=dict)
    records_answers: bool = False       # asks questions whose answers the application stores

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
    """What a subtree factory gets: the robot's skills (None when only drawing) and the
    parameters the application gave (checked against the behavior's declaration beforehand)."""
    skills: Any
    params: dict[str, Any]

    def param(self, key: str, default: Any) -> Any:
        """The application's value for `key`, or `default` when it gave none."""
        value = self.params.get(key)
        return default if value is None else value


@cache
def _load() -> tuple[dict[str, BehaviorSpec], dict[str, str]]:
    return load_plugins(GROUP, BehaviorSpec, "behavior")


def behavior_specs() -> dict[str, BehaviorSpec]:
    """Every registered macro-behavior that loaded, by name."""
    return dict(_load()[0])


def behavior_problems() -> dict[str, str]:
    """Behavior plugins that failed to load: name -> why."""
    return dict(_load()[1])


def get_behavior(name: str) -> BehaviorSpec:
    specs, problems = _load()
    if name in problems:
        raise UnknownBehaviorError(f"behavior '{name}' is not available: its plugin failed to "
                                   f"load ({problems[name]})")
    if name not in specs:
        raise UnknownBehaviorError(f"unknown behavior '{name}'; registered behaviors: "
                                   f"{', '.join(sorted(specs))}")
    return specs[name]
