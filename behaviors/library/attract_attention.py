"""AttractAttention: call out to a person who is still far away, turned towards them."""
from __future__ import annotations

from behaviors.library.common import head_and_body, repeated_call, while_facing_user
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec

CALL = "Hello there! Do you have a minute?"


def build(ctx: BehaviorContext, with_head: bool):
    return while_facing_user("AttractAttention", ctx, with_head,
                             repeated_call(ctx, ctx.param("say", CALL), every=6.0))


ATTRACT_ATTENTION = BehaviorSpec(
    name="AttractAttention",
    description="Call out every few seconds to a person who is still far away.",
    realizations=head_and_body(frozenset({"speech_out"}), build),
    parameters={"say": ParameterSpec("text", "the call, repeated every 6 s")},
)
