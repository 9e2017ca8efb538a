"""GuidePerson: lead the user to a place at a pace they can follow, and make sure they do.

The robot says `say` (e.g. "Please follow me"), drives to `place` at up to `pace` (default the
robot's top speed, a slow walk: 0.6 m/s on HOROS and PERSES), and watches the
user behind it (skills.guiding: a track behind the robot, else the rear sonars). When the user
falls more than `follow_distance` + 1.5 m behind, or is not seen, it stops and calls `call`
every 8 s until they are back within `follow_distance` + 0.5 m; after `give_up_after` s of
waiting it gives up (`guide.user_lost`, `behavior.failed`). On arrival it says `closing`, then
is done. People standing in the way are asked to let the robot pass.

HOROS looks back at the user with its pan-tilt head while it leads; PERSES, without a head,
listens with its rear sonars and, when it stops for a user it cannot see, turns round to look
for them with its camera and laser (and turns back to the way on driving on).
"""
from __future__ import annotations

import py_trees
from py_trees.common import ParallelPolicy

from behaviors.leaves import Say
from behaviors.library.common import HEAD
from behaviors.navigation_leaves import AskToPass, CallWhileWaiting, Lead, LookBack
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec, Realization
from skills.navigation.navigation import EXCUSE

START = "Please follow me."
ARRIVAL = "Here we are."
CALL = "Please follow me, I am waiting for you."
FOLLOW_DISTANCE = 1.2     # m
GIVE_UP_AFTER = 30.0      # s


def build(ctx: BehaviorContext, with_head: bool):
    lead = Lead(ctx, ctx.param("place", None), pace=ctx.param("pace", None),
                follow_distance=ctx.param("follow_distance", FOLLOW_DISTANCE),
                give_up_after=ctx.param("give_up_after", GIVE_UP_AFTER),
                turn_back=not with_head)
    helpers = [CallWhileWaiting(ctx, ctx.param("call", CALL)),
               AskToPass(ctx, ctx.param("excuse", EXCUSE))]
    if with_head:
        helpers.append(LookBack(ctx))
    guiding = py_trees.composites.Parallel(
        "Guiding", ParallelPolicy.SuccessOnSelected(children=[lead], synchronise=True),
        [lead, *helpers])
    return py_trees.composites.Sequence("GuidePerson", memory=True, children=[
        Say(ctx, ctx.param("say", START)), guiding, Say(ctx, ctx.param("closing", ARRIVAL))])


GUIDE_PERSON = BehaviorSpec(
    name="GuidePerson",
    description="Lead the user to a place, waiting when they fall behind; done on arrival.",
    realizations=(Realization("head", frozenset({"speech_out"}) | HEAD,
                              lambda ctx: build(ctx, True)),
                  Realization("body", frozenset({"speech_out"}), lambda ctx: build(ctx, False))),
    parameters={
        "place": ParameterSpec("place", "where to lead the user (a place of the map)",
                               required=True),
        "say": ParameterSpec("text", "said before leading off", default=START),
        "closing": ParameterSpec("text", "said on arrival", default=ARRIVAL),
        "call": ParameterSpec("text", "said (every 8 s) while waiting for the user", default=CALL),
        "excuse": ParameterSpec("text", "said to people standing in the way", default=EXCUSE),
        "follow_distance": ParameterSpec("distance", "how far behind the user walks",
                                         default=FOLLOW_DISTANCE),
        "give_up_after": ParameterSpec("duration", "how long to wait for a user who fell "
                                       "behind before giving up", default=GIVE_UP_AFTER),
        "pace": ParameterSpec("speed", "top speed while leading (default: the robot's "
                              "max_speed, 0.6 m/s on HOROS and PERSES; near people the profile's "
                              "lower cap applies)"),
    },
)
