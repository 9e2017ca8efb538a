"""Exactly one macro-behavior is active: switching halts the old tree before the new one ticks.

Halting stops the old root with INVALID, which py_trees passes down so each running node's
`terminate` runs once; our leaves cancel their skill goal there, and only if they started one.
"""
from __future__ import annotations

import py_trees
from py_trees.common import Status

from behaviors.registry import BehaviorContext, get_behavior


class ActiveBehavior:
    def __init__(self, capabilities: frozenset[str]) -> None:
        self.capabilities = capabilities
        self.name: str | None = None
        self.realization: str | None = None
        self.root: py_trees.behaviour.Behaviour | None = None

    def switch(self, name: str, ctx: BehaviorContext) -> str:
        """Halt the current tree, build `name`'s realization for this robot; returns its name."""
        realization = get_behavior(name).realization_for(self.capabilities)
        self.halt()
        self.root = realization.build(ctx)
        self.name, self.realization = name, realization.name
        return realization.name

    def tick(self) -> Status | None:
        """Tick the tree once; a tree that has finished (SUCCESS or FAILURE) is not ticked again,
        so a finite activity (say a text) happens once per state entry."""
        if self.root is None:
            return None
        if self.root.status not in (Status.SUCCESS, Status.FAILURE):
            self.root.tick_once()
        return self.root.status

    @property
    def status(self) -> str | None:
        """The tree's status name (RUNNING, SUCCESS, FAILURE, INVALID), None without a tree."""
        return self.root.status.name if self.root is not None else None

    def halt(self) -> None:
        if self.root is not None and self.root.status != Status.INVALID:
            self.root.stop(Status.INVALID)
        self.root = None
        self.name = self.realization = None
