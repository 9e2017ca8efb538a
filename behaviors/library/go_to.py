"""GoTo: drive to a named place of the map; done on arrival, failed with the navigation's reason.

People standing in the way are asked to let the robot pass; the navigation skill waits for
them, plans around them, or gives up (then `navigation.failure` says why)."""
from __future__ import annotations

import py_trees
from py_trees.common import ParallelPolicy

from behaviors.leaves import Say
from behaviors.navigation_leaves import AskToPass, Drive
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec, Realization
from skills.navigation.navigation import EXCUSE


def build(ctx: BehaviorContext):
    drive = Drive(ctx, ctx.param("place", None), ctx.param("speed", None))
    steps = [Say(ctx, ctx.params["say"])] if ctx.param("say", None) else []
    going = py_trees.composites.Parallel(
        "Going", ParallelPolicy.SuccessOnSelected(children=[drive], synchronise=True),
        [drive, AskToPass(ctx, ctx.param("excuse", EXCUSE))])
    return py_trees.composites.Sequence("GoTo", memory=True, children=[*steps, going])


GO_TO = BehaviorSpec(
    name="GoTo",
    description="Drive to a place of the map; done on arrival.",
    realizations=(Realization("default", frozenset(), build),),
    parameters={"place": ParameterSpec("place", "where to go (a place of the map)", required=True),
                "say": ParameterSpec("text", "said before driving off"),
                "excuse": ParameterSpec("text", "said to people standing in the way",
                                        default=EXCUSE),
                "speed": ParameterSpec("speed", "top speed (default: the robot's)")},
)
