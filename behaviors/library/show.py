"""Show: put a text (and a picture) on the touch screen, say something if asked to, and keep it
shown for a while; done after `duration`. The screen is cleared when the state is left."""
from __future__ import annotations

import py_trees

from behaviors.leaves import HoldStill, Pause, Say, ShowInfo
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec, Realization

DURATION = 10.0     # s a screen stays before the behavior is done, unless told otherwise


def build(ctx: BehaviorContext):
    steps = [HoldStill(ctx), ShowInfo(ctx, ctx.param("show", ""), ctx.param("picture", None))]
    if ctx.param("say", None):
        steps.append(Say(ctx, ctx.params["say"]))
    steps.append(Pause(ctx, ctx.param("duration", DURATION)))
    return py_trees.composites.Sequence("Show", memory=True, children=steps)


SHOW = BehaviorSpec(
    name="Show",
    description="Show a text and picture on the touch screen for a while.",
    realizations=(Realization("default", frozenset({"touch_screen"}), build),),
    parameters={"show": ParameterSpec("text", "the text on the screen", required=True),
                "picture": ParameterSpec("picture", "a picture shown with the text"),
                "say": ParameterSpec("text", "said while the screen is shown"),
                "duration": ParameterSpec("duration", "how long before the behavior is done",
                                          default=DURATION)},
)
