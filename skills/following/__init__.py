"""Following a customer, in parts a reader can hold one at a time:

- `follower`: the skill and its phase machine (following, waiting, hidden, searching, gave up);
- `identity`: who the customer is (her belief, look, gate, swaps);
- `keeping`: keeping the distance (driving behind, waiting near, giving way);
- `searching`: what the robot does while she is unseen;
- `room`: where the robot fits;
- `pace`: asking a customer who outpaces the robot to wait.
"""
from skills.following.follower import (CALL, FOLLOWING, GAVE_UP, GAVE_UP_REASON, HIDDEN,
                                       IDLE_PHASE, NO_CUSTOMER, PHASES, SEARCHING, WAITING,
                                       FollowParams, FollowState, Following)

__all__ = ["CALL", "FOLLOWING", "GAVE_UP", "GAVE_UP_REASON", "HIDDEN", "IDLE_PHASE",
           "NO_CUSTOMER", "PHASES", "SEARCHING", "WAITING", "FollowParams", "FollowState",
           "Following"]
