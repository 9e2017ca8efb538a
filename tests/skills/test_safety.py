import math

from robots.profile import load_profile
from skills.safety import STOP_DISTANCE, arbitrate

LIMITS = load_profile("horos").limits


def call(v, w, link=True, free=math.inf, person=math.inf, behind=math.inf):
    return arbitrate(v, w, link_fresh=link, free_ahead=free, free_behind=behind,
                     nearest_person=person, limits=LIMITS)


def test_a_safe_command_passes_unchanged():
    assert call(0.2, 0.1) == (0.2, 0.1, "")


def test_stale_data_stops_everything():
    v, w, why = call(0.2, 0.5, link=False)
    assert (v, w) == (0.0, 0.0) and "stale" in why


def test_not_a_number_becomes_zero():
    assert call(math.nan, 0.3)[:2] == (0.0, 0.0)
    assert call(0.1, math.inf)[:2] == (0.0, 0.0)


def test_obstacle_ahead_stops_forward_motion_but_not_turning_or_backing():
    v, w, why = call(0.3, 0.2, free=STOP_DISTANCE / 2)
    assert v == 0.0 and w == 0.2 and "obstacle" in why
    assert call(-0.1, 0.0, free=0.0)[0] == -0.1


def test_obstacle_behind_or_no_sensor_there_stops_backing_but_not_driving_forward():
    v, w, why = call(-0.1, 0.2, behind=STOP_DISTANCE / 2)
    assert v == 0.0 and w == 0.2 and "behind" in why
    assert call(-0.1, 0.0, behind=0.0)[0] == 0.0          # a robot that cannot see behind
    assert call(0.2, 0.0, behind=0.0)[0] == 0.2
    assert call(-0.1, 0.0, behind=1.0)[0] == -0.1


def test_speed_is_capped_near_people_and_by_the_profile():
    v, _, why = call(0.5, 0.0, person=LIMITS.near_people_distance / 2)
    assert v == LIMITS.max_speed_near_people and "person" in why
    assert call(5.0, 0.0)[0] == LIMITS.max_speed
    assert call(0.0, -9.0)[1] == -LIMITS.max_turn_rate


def test_never_drives_towards_a_person_inside_the_minimum_distance():
    def with_people(v, ahead=math.inf, rear=math.inf, minimum=0.8):
        return arbitrate(v, 0.3, link_fresh=True, free_ahead=math.inf, free_behind=math.inf,
                         nearest_person=min(ahead, rear), limits=LIMITS, person_ahead=ahead,
                         person_behind=rear, min_person_distance=minimum)
    v, w, why = with_people(0.1, ahead=0.6)
    assert (v, w) == (0.0, 0.3) and "0.60 m ahead" in why and "0.80" in why
    assert with_people(-0.1, ahead=0.6)[0] == -0.1        # backing away from her is allowed
    v, _, why = with_people(-0.1, rear=0.5)
    assert v == 0.0 and "behind" in why
    assert with_people(0.1, rear=0.5)[0] == 0.1           # driving away from him is allowed
    assert with_people(0.1, ahead=0.9)[0] == 0.1          # outside the minimum
    assert with_people(0.1, ahead=0.7, minimum=0.6)[0] == 0.1
