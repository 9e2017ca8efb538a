"""Idle: stand still, head centred, and forget the last person's survey session."""
from __future__ import annotations

import py_trees

from behaviors.leaves import ResetSurvey, StandStill
from behaviors.registry import BehaviorContext, BehaviorSpec, Realization


def build(ctx: BehaviorContext) -> py_trees.behaviour.Behaviour:
    return py_trees.composites.Sequence("Idle", memory=True,
                                        children=[ResetSurvey(ctx), StandStill(ctx)])


IDLE = BehaviorSpec(
    name="Idle",
    description="Stand still and wait; the next person starts a fresh survey.",
    realizations=(Realization("default", frozenset(), build),),
)
