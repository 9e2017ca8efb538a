"""LookAt: turn to the user and keep facing them without a word (pan-tilt head on HOROS, whole
body on PERSES) — the silent way of attracting attention, an alternative to FaceUser's greeting
or AttractAttention's calls at a choice point (issue 27)."""
from __future__ import annotations

from behaviors.library.common import head_and_body, orient, together
from behaviors.leaves import StandStill
from behaviors.registry import BehaviorContext, BehaviorSpec


def build(ctx: BehaviorContext, with_head: bool):
    children = [orient(ctx, with_head)]
    if with_head:
        children.append(StandStill(ctx))
    return together("LookAt", *children)


LOOK_AT = BehaviorSpec(
    name="LookAt",
    description="Turn to the user and keep facing them, silently.",
    realizations=head_and_body(frozenset(), build),
    parameters={},
)
