"""Building blocks the bundled macro-behaviors share: orienting towards the user, calling out."""
from __future__ import annotations

import py_trees
from py_trees.common import ParallelPolicy

from behaviors.leaves import LookAtUser, Pause, Say, StandStill, TurnToUser
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, Realization

SAY = ParameterSpec("text", "what the robot says")

HEAD = frozenset({"pan_tilt"})
BODY = frozenset()


def orient(ctx: BehaviorContext, with_head: bool) -> py_trees.behaviour.Behaviour:
    """Keep facing the user: the pan-tilt head where there is one, else the whole body."""
    return LookAtUser(ctx) if with_head else TurnToUser(ctx)


def while_facing_user(name: str, ctx: BehaviorContext, with_head: bool,
                      activity: py_trees.behaviour.Behaviour) -> py_trees.composites.Parallel:
    """Run `activity` while facing the user; with a head, the base also holds still."""
    children = [activity, orient(ctx, with_head)]
    if with_head:
        children.append(StandStill(ctx))
    return together(name, *children)


def facing_user_until_done(name: str, ctx: BehaviorContext, with_head: bool,
                           activity: py_trees.behaviour.Behaviour) -> py_trees.composites.Parallel:
    """Run `activity` while facing the user; done when the activity is (facing then stops)."""
    children = [activity, orient(ctx, with_head)]
    if with_head:
        children.append(StandStill(ctx))
    return py_trees.composites.Parallel(
        name, ParallelPolicy.SuccessOnSelected(children=[activity], synchronise=True), children)


def together(name: str, *children: py_trees.behaviour.Behaviour) -> py_trees.composites.Parallel:
    """Run children side by side; finished ones are not ticked again."""
    return py_trees.composites.Parallel(name, ParallelPolicy.SuccessOnAll(synchronise=True),
                                        list(children))


def repeated_call(ctx: BehaviorContext, text: str, every: float) -> py_trees.behaviour.Behaviour:
    """Say `text`, wait `every` seconds, and again, until the behavior is switched off."""
    once = py_trees.composites.Sequence("Call", memory=True,
                                        children=[Say(ctx, text), Pause(ctx, every)])
    return py_trees.decorators.Repeat("Repeat call", once, num_success=-1)


def head_and_body(needs: frozenset[str], build) -> tuple[Realization, Realization]:
    """Two realizations of one behavior: with the pan-tilt head (preferred) and with the body."""
    return (Realization("head", needs | HEAD, lambda ctx: build(ctx, True)),
            Realization("body", needs | BODY, lambda ctx: build(ctx, False)))
