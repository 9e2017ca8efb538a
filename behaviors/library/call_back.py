"""CallBack: the user left before finishing; ask them to come back, turned the way they went."""
from __future__ import annotations

from behaviors.leaves import StandStill
from behaviors.library.common import repeated_call, together
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec, Realization

CALL = "Please come back, the survey is not finished yet!"


def build(ctx: BehaviorContext):
    return together("CallBack", repeated_call(ctx, ctx.param("say", CALL), every=8.0),
                    StandStill(ctx))


CALL_BACK = BehaviorSpec(
    name="CallBack",
    description="Call the user back to finish the survey.",
    realizations=(Realization("default", frozenset({"speech_out"}), build),),
    parameters={"say": ParameterSpec("text", "the call, repeated every 8 s")},
)
