"""FollowCustomer: keep the customer at a following distance through the store; find them again.

The work is the `following` skill's (skills/following/): driving behind the customer through
navigation, predicting where a hidden customer went, searching, calling out, giving up. The
behavior starts it on the user (the customer who asked), keeps the pan-tilt head on them where
there is one (HOROS; PERSES turns its body, which the skill does when it waits), and fails when
the skill gives up, so a state graph moves on with `behavior.failed` or the `follow.*` percepts.
"""
from __future__ import annotations

from py_trees.common import Status

from behaviors.leaves import LookAtUser, SkillLeaf
from behaviors.library.common import together
from behaviors.parameters import ParameterSpec
from behaviors.registry import BehaviorContext, BehaviorSpec, Realization
from skills.navigation.navigation import EXCUSE

CALL = "Where are you? I cannot see you any more."


class Follow(SkillLeaf):
    """Follow the user until the state is left; FAILURE when the skill gives up."""

    def __init__(self, ctx: BehaviorContext) -> None:
        super().__init__("Follow customer", ctx)

    def start(self) -> None:
        p = self.ctx
        if p.param("say", None) and self.skills.speech is not None:
            self.skills.speech.say(p.params["say"], self.now)
        self.skills.require("following").follow(
            self.now, distance=p.param("distance", 1.2), min_distance=p.param("min_distance", 0.8),
            give_up_after=p.param("give_up", 30.0), search_after=p.param("search_after", 4.0),
            call=p.param("call", CALL), excuse=p.param("excuse", EXCUSE))

    def update(self) -> Status:
        status = self.skills.following.status
        if status.failed:
            self.feedback_message = status.reason
            return Status.FAILURE
        self.feedback_message = status.reason
        return Status.RUNNING

    def finish(self, new_status: Status) -> None:
        self.skills.following.cancel(self.now)


def _build(ctx: BehaviorContext, with_head: bool):
    follow = Follow(ctx)
    if not with_head:
        return follow
    return together("FollowCustomer", follow, LookAtUser(ctx))


FOLLOW_CUSTOMER = BehaviorSpec(
    name="FollowCustomer",
    description="Follow the customer at a distance through the store; when they are hidden or "
                "lost, predict where they went, search, call out; give up (fail) after a time.",
    realizations=(
        Realization("head", frozenset({"pan_tilt", "speech_out"}), lambda ctx: _build(ctx, True)),
        Realization("body", frozenset({"speech_out"}), lambda ctx: _build(ctx, False)),
    ),
    parameters={
        "say": ParameterSpec("text", "said when following begins"),
        "distance": ParameterSpec("distance", "following distance, robot centre to customer",
                                  default=1.2),
        "min_distance": ParameterSpec("distance", "the robot never drives closer than this",
                                      default=0.8),
        "search_after": ParameterSpec("duration", "hidden this long, the robot searches and calls",
                                      default=4.0),
        "give_up": ParameterSpec("duration", "not found for this long, the behavior fails",
                                 default=30.0),
        "call": ParameterSpec("text", "what the robot calls out while searching", default=CALL),
        "excuse": ParameterSpec("text", "said to people standing in the way", default=EXCUSE),
    },
)
