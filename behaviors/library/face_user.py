"""FaceUser: greet the person and keep facing them (pan-tilt head on HOROS, whole body on PERSES)."""
from __future__ import annotations

from behaviors.leaves import Say, StandStill
from behaviors.library.common import head_and_body, orient, together
from behaviors.registry import BehaviorContext, BehaviorSpec

GREETING = "Hello! Please come closer."


def build(ctx: BehaviorContext, with_head: bool):
    children = [Say(ctx, ctx.param("say", GREETING)), orient(ctx, with_head)]
    if with_head:
        children.append(StandStill(ctx))
    return together("FaceUser", *children)


FACE_USER = BehaviorSpec(
    name="FaceUser",
    description="Greet the user and keep facing them.",
    realizations=head_and_body(frozenset({"speech_out"}), build),
    parameters={"say": "the greeting"},
)
