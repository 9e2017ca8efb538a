"""FaceUser: greet the person and keep facing them (pan-tilt head on HOROS, whole body on PERSES)."""
from __future__ import annotations

from behaviors.leaves import Say
from behaviors.library.common import head_and_body, while_facing_user
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec

GREETING = "Hello! Please come closer."


def build(ctx: BehaviorContext, with_head: bool):
    return while_facing_user("FaceUser", ctx, with_head, Say(ctx, ctx.param("say", GREETING)))


FACE_USER = BehaviorSpec(
    name="FaceUser",
    description="Greet the user and keep facing them.",
    realizations=head_and_body(frozenset({"speech_out"}), build),
    parameters={"say": ParameterSpec("text", "the greeting")},
)
