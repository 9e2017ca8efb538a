"""Say: say a text, facing the user; done when it has been said (then `behavior.done` holds)."""
from __future__ import annotations

import py_trees

from behaviors.leaves import HoldStill, Say
from behaviors.library.common import SAY, facing_user_until_done, head_and_body
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec


def build(ctx: BehaviorContext, with_head: bool):
    saying = py_trees.composites.Sequence("Say", memory=True, children=[
        HoldStill(ctx), Say(ctx, ctx.param("say", ""))])
    return facing_user_until_done("Say", ctx, with_head, saying)


SAY_BEHAVIOR = BehaviorSpec(
    name="Say",
    description="Say a text while facing the user; done when it is said.",
    realizations=head_and_body(frozenset({"speech_out"}), build),
    parameters={"say": ParameterSpec("text", SAY.doc, required=True)},
)
