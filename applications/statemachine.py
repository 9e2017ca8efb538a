"""The interpreter of a state graph: each tick, try the current state's transitions in order.

Transitions are tried by priority, then in file order (`State.ordered_transitions`); the first
whose condition holds fires. The model is plain data (`applications.graph.model`), so a new
version of the application can be swapped in between two ticks (hot reload).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from applications.graph.model import Application, State, Transition


@dataclass(frozen=True)
class Fired:
    source: str
    target: str
    transition: Transition
    t: float
    elapsed: float = 0.0       # time in the source state when it fired


class StateMachine:
    def __init__(self, app: Application, now: float) -> None:
        self.app = app
        self.state: State = app.initial_state
        self.entered_at = now

    def time_in_state(self, now: float) -> float:
        return max(0.0, now - self.entered_at)

    @property
    def finished(self) -> bool:
        return self.state.final

    def step(self, percepts: Mapping[str, Any], now: float) -> Fired | None:
        """Fire at most one transition of the current state; returns it, or None."""
        elapsed = self.time_in_state(now)
        for transition in self.state.ordered_transitions():
            if transition.condition.evaluate(percepts, elapsed):
                fired = Fired(self.state.name, transition.target, transition, now, elapsed)
                self.state = self.app.states[transition.target]
                self.entered_at = now
                return fired
        return None

    def replace(self, app: Application, now: float) -> bool:
        """Swap in a new version of the application; True when the current state had to change.

        The current state is kept (with its time in state) when the new version still has it;
        otherwise the machine enters the new initial state.
        """
        self.app = app
        if self.state.name in app.states:
            self.state = app.states[self.state.name]
            return False
        self.state = app.initial_state
        self.entered_at = now
        return True
