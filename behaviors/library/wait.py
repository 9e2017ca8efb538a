"""Wait: stand still; done after `duration` when one is given. Unlike Idle, it keeps the
person's session (their answers), so an application can pause in the middle of a dialog."""
from __future__ import annotations

import py_trees

from behaviors.leaves import HoldStill, Pause, StandStill
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec, Realization


def build(ctx: BehaviorContext):
    duration = ctx.param("duration", None)
    last = Pause(ctx, duration) if duration is not None else StandStill(ctx)
    return py_trees.composites.Sequence("Wait", memory=True, children=[HoldStill(ctx), last])


WAIT = BehaviorSpec(
    name="Wait",
    description="Stand still; done after the duration, if one is given.",
    realizations=(Realization("default", frozenset(), build),),
    parameters={"duration": ParameterSpec("duration", "how long to wait (none: until a "
                                                      "transition leaves the state)")},
)
