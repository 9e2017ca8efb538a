"""Asking a customer who outpaces the robot to wait (skills.following.pace): the follower
asks once she pulls away faster than it can drive, not again for a while, says so when it
loses her, and never asks one it can keep up with."""
from __future__ import annotations

from follow_fakes import Speech, follower, track
from skills.following import HIDDEN, SEARCHING
from skills.following.pace import ASK, ASK_AGAIN, LOST, PaceWatch


def walk_away(following, perception, speed, seconds, start=0.0, x0=1.2):
    """Her track walks away along x at `speed` from `x0` (the robot stands at the origin)."""
    k = 0
    while k * 0.1 <= seconds + 1e-9:
        t = start + k * 0.1
        perception.believed = (track(1, x0 + speed * (t - start), 0.0, t, vx=speed),)
        following.sense(t)
        k += 1
    return start + k * 0.1, x0 + speed * (k - 1) * 0.1


def started(speed):
    speech = Speech()
    following, perception = follower(speech=speech)
    perception.believed = (track(1, 1.2, 0.0, 0.0, vx=speed),)
    assert following.follow(0.0, target=1).running
    return following, perception, speech


def asks(speech, words=ASK):
    return [t for t, text in speech.said if text == words]


def test_asks_once_when_she_walks_away_faster_than_the_robot_can_drive():
    following, perception, speech = started(1.4)
    walk_away(following, perception, 1.4, 12.0)       # PERSES tops out at 0.6 m/s
    said = asks(speech)
    assert len(said) == 1                              # asked, and did not nag
    assert 1.0 <= said[0] <= 3.0                       # as soon as the gap is clearly growing


def test_asks_again_only_after_a_while():
    following, perception, speech = started(1.4)
    walk_away(following, perception, 1.4, ASK_AGAIN + 4.0)
    said = asks(speech)
    assert len(said) == 2 and said[1] - said[0] >= ASK_AGAIN


def test_never_asks_a_customer_it_can_keep_up_with():
    # she walks at 0.5 m/s and the (fake) robot stands: the gap grows, but the robot could
    # close it; a blocked way or a search is not hers to wait for
    following, perception, speech = started(0.5)
    walk_away(following, perception, 0.5, 15.0)
    assert speech.said == []


def test_never_asks_a_shopper_who_catches_up_in_a_short_burst():
    # she usually walks at 0.5 m/s; held up, she catches up at 0.65 m/s for 1.5 s (faster
    # than PERSES's 0.6 for a moment) while the robot is held up too: she is no fast walker
    following, perception, speech = started(0.5)
    t, x = walk_away(following, perception, 0.5, 6.0)
    walk_away(following, perception, 0.65, 1.5, start=t, x0=x)
    assert speech.said == []


def test_says_it_lost_her_once_when_she_outpaced_it_out_of_sight():
    following, perception, speech = started(1.4)
    t, _ = walk_away(following, perception, 1.4, 4.0)
    lost_at = t
    perception.believed = ()
    for k in range(60):                                # 6 s unseen
        following.sense(t + 0.1 * k)
    assert following.state.phase in (HIDDEN, SEARCHING)
    said = asks(speech, LOST)
    assert len(said) == 1 and said[0] - lost_at <= 2.0


def test_a_loss_of_a_customer_it_kept_up_with_is_not_announced():
    following, perception, speech = started(0.5)
    t, _ = walk_away(following, perception, 0.5, 4.0, x0=1.7)
    perception.believed = ()
    for k in range(30):
        following.sense(t + 0.1 * k)
    assert asks(speech, LOST) == []


def test_the_watch_alone_counts_the_gap_beyond_the_setpoint_and_the_top_speed():
    watch = PaceWatch()
    said = [watch.seen(0.1 * k, 0.8 * 0.1 * k, 1.4, 0.6) for k in range(40)]
    assert said.count(ASK) == 1
    assert 0.8 * 0.1 * said.index(ASK) >= 1.0          # only once 1 m behind
    faster_robot = PaceWatch()
    assert all(faster_robot.seen(0.1 * k, 0.8 * 0.1 * k, 1.4, 1.5) is None for k in range(40))


def test_asks_a_customer_who_strolls_on_while_people_near_hold_the_robot_to_their_cap():
    # she walks at 0.5 m/s, which PERSES could match on an empty floor (the test above), but
    # shoppers near it hold it to the near-people cap, 0.3 m/s: no speed of its own closes
    # the gap (crowd10 seed 0: 3 m behind in 15 s, then lost for good without a word)
    following, perception, speech = started(0.5)
    following.motion.people_near = True
    walk_away(following, perception, 0.5, 12.0)
    said = asks(speech)
    assert len(said) == 1 and said[0] <= 4.0
