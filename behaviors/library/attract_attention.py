"""AttractAttention: call out to a person who is still far away, turned towards them."""
from __future__ import annotations

from behaviors.leaves import StandStill
from behaviors.library.common import head_and_body, orient, repeated_call, together
from behaviors.registry import BehaviorContext, BehaviorSpec

CALL = "Hello there! Do you have a minute?"


def build(ctx: BehaviorContext, with_head: bool):
    children = [repeated_call(ctx, ctx.param("say", CALL), every=6.0), orient(ctx, with_head)]
    if with_head:
        children.append(StandStill(ctx))
    return together("AttractAttention", *children)


ATTRACT_ATTENTION = BehaviorSpec(
    name="AttractAttention",
    description="Call out every few seconds to a person who is still far away.",
    realizations=head_and_body(frozenset({"speech_out"}), build),
    parameters={"say": "the call"},
)
