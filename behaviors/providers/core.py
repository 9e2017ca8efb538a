"""The core percepts: people and the user, speech, motion, the base, and the active behavior."""
from __future__ import annotations

from behaviors.percepts import PerceptContext, PerceptProvider, spec

APPROACHING = 0.1          # m/s towards the robot

SPECS = (
    spec("people.count", "int", None, (0, 1000), "people tracked around the robot now"),
    spec("people.new", "int", None, (0, 1000),
         "people tracked now whose track was confirmed after the active macro-behavior started, "
         "i.e. since the current state was entered"),
    spec("user.present", "bool", doc="an interaction partner is selected among the tracked people"),
    spec("user.distance", "float", "m", (0.0, 30.0),
         "distance from the robot's centre to the user; absent when there is no user"),
    spec("user.approaching", "bool", doc="the user's speed towards the robot exceeds 0.1 m/s"),
    spec("user.left", "bool",
         doc="the user selected during the active macro-behavior is no longer tracked"),
    spec("speech.busy", "bool", doc="the robot is still speaking"),
    spec("motion.failed", "bool", doc="the motion skill reported failure"),
    spec("robot.fault", "bool", doc="the base or a wired laser reported a fault (link down, stale sensors, stall)"),
    spec("behavior.done", "bool",
         doc="the active macro-behavior has finished its work (e.g. Say has said its text)"),
    spec("behavior.failed", "bool", doc="the active macro-behavior gave up"),
)


def read(ctx: PerceptContext) -> dict:
    tracks = ctx.fresh("people/tracks", ())
    user = ctx.fresh("people/user")
    if user is not None:
        ctx.users_seen.add(user.id)
    ids = {t.id for t in tracks}
    approach = ctx.fresh("people/user_approach")
    motion = ctx.skills.blackboard.value("skills/motion/status")
    return {
        "people.count": len(tracks),
        "people.new": sum(1 for t in tracks if (t.confirmed_at or t.born) >= ctx.since),
        "user.present": user is not None,
        "user.distance": ctx.fresh("people/user_distance"),
        "user.approaching": approach is not None and approach > APPROACHING,
        "user.left": bool(ctx.users_seen - ids),
        "speech.busy": bool(ctx.fresh("speech/busy", False)),
        "motion.failed": bool(motion and motion.failed),
        "robot.fault": not ctx.fresh("robot/link", False),
        "behavior.done": ctx.behavior_status == "SUCCESS",
        "behavior.failed": ctx.behavior_status == "FAILURE",
    }


CORE = PerceptProvider("core", SPECS, read)
