"""The tracker: filter arithmetic, association, life cycle, occlusion, duplicates, ego frame."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from skills.people import (CONFIRMED, LOST, TENTATIVE, PeopleTracker, TrackerParams,
                           robot_to_world)

R = np.eye(2) * 0.05 ** 2   # the camera-like detector's noise


def run(tracker, frames):
    """Feed (t, [(x, y), ...]) frames; return the tracks after the last one."""
    out = []
    for t, points in frames:
        out = tracker.update(t, [(x, y, R) for x, y in points])
    return out


def test_first_prediction_and_update_match_hand_computed_values():
    tracker = PeopleTracker(TrackerParams(accel_noise=1.0, initial_speed_sigma=1.0))
    r = np.eye(2) * 0.01
    born = tracker.update(0.0, [(0.0, 0.0, r)])
    assert born[0].x == 0.0 and born[0].vx == 0.0 and born[0].cov[0, 0] == pytest.approx(0.01)
    (track,) = tracker.update(0.1, [(0.1, 0.0, r)])
    # Predicted with dt = 0.1, q = 1: Pxx = 0.01 + 0.1^2 * 1 + 0.1^3 / 3 = 0.0203333,
    # Pxv = 0.1 * 1 + 0.1^2 / 2 = 0.105, Pvv = 1 + 0.1 = 1.1. S = Pxx + 0.01 = 0.0303333.
    # Gains: Kx = 0.0203333 / 0.0303333 = 0.670330, Kv = 0.105 / 0.0303333 = 3.461538.
    assert track.x == pytest.approx(0.0670330, abs=1e-6)
    assert track.vx == pytest.approx(0.3461538, abs=1e-6)
    assert track.y == pytest.approx(0.0) and track.vy == pytest.approx(0.0)
    # Posterior Pxx = Pxx * R / S = 0.0203333 * 0.01 / 0.0303333 = 0.0067033.
    assert track.cov[0, 0] == pytest.approx(0.0067033, abs=1e-6)
    assert track.cov[0, 1] == pytest.approx(0.0)


def test_pure_prediction_moves_a_track_by_its_velocity():
    tracker = PeopleTracker()
    frames = [(k * 0.1, [(0.5 * k * 0.1, 1.0)]) for k in range(30)]
    before = run(tracker, frames)[0]
    (after,) = tracker.update(3.0, [])
    assert after.vx == pytest.approx(0.5, abs=0.02)
    assert after.x == pytest.approx(before.x + before.vx * 0.1, abs=1e-9)
    assert after.cov[0, 0] > before.cov[0, 0]


def test_birth_confirmation_loss_and_deletion():
    p = TrackerParams()
    tracker = PeopleTracker(p)
    statuses = []
    for k in range(5):
        statuses.append(tracker.update(k * 0.1, [(2.0, 1.0, R)])[0].status)
    assert statuses[:2] == [TENTATIVE, TENTATIVE] and statuses[2:] == [CONFIRMED] * 3
    (track,) = tracker.tracks()
    assert track.confirmed_at == pytest.approx(0.2) and track.born == 0.0
    seen = {}
    t = 0.4
    while tracker.tracks():
        t = round(t + 0.1, 10)
        tracks = tracker.update(t, [])
        seen[t] = tracks[0].status if tracks else None
    assert seen[0.5] == CONFIRMED                        # one missed frame is normal
    assert seen[0.8] == LOST
    assert seen[1.9] == LOST and seen[2.0] is None       # deleted after 1.5 s unseen


def test_a_single_false_positive_never_becomes_a_track():
    tracker = PeopleTracker()
    tracker.update(0.0, [(3.0, 3.0, R)])
    for k in range(1, 5):
        tracks = tracker.update(k * 0.1, [])
    assert tracks == []


def test_crossing_paths_keep_their_ids():
    """Two people walk at 1.4 m/s on crossing diagonals, passing 0.6 m from each other."""
    rng = np.random.default_rng(1)
    tracker = PeopleTracker()
    ids_a, ids_b = set(), set()
    for k in range(61):
        t = k * 0.1
        a = (-3.0 + t, -3.0 + t)
        b = (-2.4 + t, 3.0 - t)
        noisy = [(x + rng.normal(0, 0.05), y + rng.normal(0, 0.05)) for x, y in (a, b)]
        tracks = tracker.update(t, [(x, y, R) for x, y in noisy])
        if k >= 3:
            for track in tracks:
                nearest_a = math.dist((track.x, track.y), a) < math.dist((track.x, track.y), b)
                (ids_a if nearest_a else ids_b).add(track.id)
    assert len(ids_a) == 1 and len(ids_b) == 1 and ids_a != ids_b


def test_a_person_hidden_for_one_second_keeps_the_id():
    tracker = PeopleTracker()
    ids = []
    for k in range(60):
        t = k * 0.1
        hidden = 20 <= k < 30                                  # one second without detections
        points = [] if hidden else [(-2.0 + 0.8 * t, 1.0)]
        tracks = tracker.update(t, [(x, y, R) for x, y in points])
        if k >= 3:
            ids.append(tracks[0].id)
            if hidden and k >= 24:
                assert tracks[0].status == LOST
    assert set(ids) == {ids[0]} and tracker.tracks()[0].status == CONFIRMED


def test_camera_and_laser_seeing_the_same_person_make_one_track():
    tracker = PeopleTracker()
    laser = np.eye(2) * 0.08 ** 2
    for k in range(10):
        t = k * 0.1
        tracks = tracker.update(t, [(1.0, 0.0, R), (1.06, 0.04, laser), (3.0, 0.0, R)])
    assert len(tracks) == 2


def test_frames_must_not_go_back_in_time():
    tracker = PeopleTracker()
    tracker.update(1.0, [])
    with pytest.raises(ValueError, match="older"):
        tracker.update(0.5, [])


def test_a_still_person_seen_from_a_turning_and_driving_robot_stays_still():
    """Ego-motion compensation: detections come in the robot frame and are moved to the world
    frame with the robot's pose before tracking, so the robot's own motion cancels out."""
    tracker = PeopleTracker()
    rng = np.random.default_rng(3)
    person = (3.0, 1.0)
    for k in range(50):
        t = k * 0.1
        pose = (0.3 * t, 0.0, 0.8 * t)                     # drives 0.3 m/s, turns 0.8 rad/s
        dx, dy = person[0] - pose[0], person[1] - pose[1]
        c, s = math.cos(pose[2]), math.sin(pose[2])
        local = (c * dx + s * dy + rng.normal(0, 0.05), -s * dx + c * dy + rng.normal(0, 0.05))
        tracks = tracker.update(t, [robot_to_world(*local, R, pose)])
    (track,) = tracks
    assert math.dist((track.x, track.y), person) < 0.1
    assert track.speed < 0.3


def test_laser_only_candidates_update_but_never_confirm_when_the_camera_must_confirm():
    tracker = PeopleTracker(TrackerParams(confirming_sources=("camera",)))
    laser = np.eye(2) * 0.08 ** 2
    for k in range(20):
        tracks = tracker.update(k * 0.1, [(2.0, 2.0, laser, "laser"), (-1.0, 1.0, R, "camera")])
    by_place = {round(tr.x): tr.status for tr in tracks}
    assert by_place == {2: TENTATIVE, -1: CONFIRMED}


def test_laser_detections_keep_a_camera_confirmed_track_alive():
    tracker = PeopleTracker(TrackerParams(confirming_sources=("camera",)))
    laser = np.eye(2) * 0.08 ** 2
    for k in range(5):
        tracker.update(k * 0.1, [(1.0, 0.0, R, "camera")])
    for k in range(5, 40):                                  # the camera loses them for 3.5 s
        tracks = tracker.update(k * 0.1, [(1.0, 0.0, laser, "laser")])
    assert [tr.status for tr in tracks] == [CONFIRMED]
    # ... but the track says when the camera last saw it (laser legs may be a cart's wheels)
    assert tracks[0].last_seen == pytest.approx(3.9)
    assert tracks[0].confirmed_seen == pytest.approx(0.4)


def test_without_a_confirming_source_every_detection_confirms_the_person():
    tracker = PeopleTracker()
    for k in range(5):
        (track,) = tracker.update(k * 0.1, [(1.0, 0.0, R, "laser")])
    assert track.confirmed_seen == track.last_seen == pytest.approx(0.4)


def test_the_imm_knows_a_person_who_stopped_is_standing():
    rng = np.random.default_rng(5)
    speeds = {}
    for model in ("cv", "imm"):
        tracker = PeopleTracker(TrackerParams(model=model))
        standing = []
        for k in range(80):
            t = k * 0.1
            x = min(t, 4.0)                                 # walks 1 m/s for 4 s, then stands
            tracks = tracker.update(t, [(x + rng.normal(0, 0.05), rng.normal(0, 0.05), R)])
            if k == 39:
                assert tracks[0].vx == pytest.approx(1.0, abs=0.35)
            if k >= 60:
                standing.append(tracks[0].speed)
        speeds[model] = np.median(standing)
    assert speeds["imm"] < 0.05 < speeds["cv"]


@settings(max_examples=25, deadline=None)
@given(n=st.integers(1, 8), seed=st.integers(0, 10_000))
@example(n=5, seed=716).via("a CI run: a sixth track for five people before leftover_reach")
@example(n=1, seed=1567).via("one person, split in two before leftover_reach")
@example(n=8, seed=254).via("a walking pace of 1.95 m/s learnt from two detections")
def test_people_standing_apart_get_one_track_each_whatever_the_detection_order(n, seed):
    rng = np.random.default_rng(seed)
    people = np.column_stack((np.arange(n) * 0.9, rng.uniform(-3, 3, n)))
    tracker = PeopleTracker()
    ids = None
    for k in range(15):
        points = people + rng.normal(0, 0.05, people.shape)
        order = rng.permutation(n)
        tracks = tracker.update(k * 0.1, [(x, y, R) for x, y in points[order]])
        if k >= 2:
            owner = {tr.id: int(np.argmin(np.hypot(*(people - (tr.x, tr.y)).T))) for tr in tracks}
            ids = ids or owner
            assert owner == ids
    assert len(ids) == n and sorted(ids.values()) == list(range(n))


def test_a_person_walking_behind_another_keeps_the_id():
    """The robot at the origin; A stands 2 m ahead, B walks across 3.5 m ahead at 0.8 m/s and
    is hidden by A while within A's shadow (|y| < 0.44 m: about 1.1 s)."""
    rng = np.random.default_rng(7)
    tracker = PeopleTracker()
    seen_ids = {"A": set(), "B": set()}
    hidden_frames = 0
    for k in range(70):
        t = k * 0.1
        a, b = (2.0, 0.0), (3.5, -2.8 + 0.8 * t)
        hidden = abs(b[1]) < 0.44
        hidden_frames += hidden
        points = [a] if hidden else [a, b]
        tracks = tracker.update(t, [(x + rng.normal(0, 0.05), y + rng.normal(0, 0.05), R)
                                    for x, y in points])
        for tr in tracks:
            if tr.status == TENTATIVE:
                continue
            name = "A" if math.dist((tr.x, tr.y), a) < math.dist((tr.x, tr.y), b) else "B"
            seen_ids[name].add(tr.id)
    assert hidden_frames >= 10
    assert len(seen_ids["A"]) == 1 and len(seen_ids["B"]) == 1


def test_an_unknown_motion_model_is_refused_with_the_allowed_ones():
    with pytest.raises(ValueError, match="'cv'.*'imm'"):
        PeopleTracker(TrackerParams(model="ca"))


def test_noise_free_detections_are_tracked_and_broken_ones_refused():
    tracker = PeopleTracker()
    for k in range(5):
        tracks = tracker.update(k * 0.1, [(1.0, 2.0, np.zeros((2, 2)))])
    assert [(tr.x, tr.y, tr.status) for tr in tracks] == [(1.0, 2.0, CONFIRMED)]
    assert np.isfinite(tracks[0].cov).all()
    before = tracker.tracks()
    with pytest.raises(ValueError, match="detection 1 of this frame is not finite"):
        tracker.update(1.0, [(1.0, 2.0, R), (math.nan, 0.0, R)])
    with pytest.raises(ValueError, match="2x2"):
        tracker.update(1.0, [(1.0, 2.0, np.eye(3))])
    after = tracker.tracks()                                 # the bad frames changed nothing
    assert [(a.x, a.vx, a.cov.tolist()) for a in after] == [
        (b.x, b.vx, b.cov.tolist()) for b in before]


def test_a_track_carries_the_newest_camera_view_of_the_person():
    tracker = PeopleTracker()
    red, blue = (0.7, 0.1, 0.1, 0.1), (0.1, 0.1, 0.1, 0.7)
    tracker.update(0.0, [(1.0, 0.0, R, "camera", red)])
    (track,) = tracker.update(0.1, [(1.0, 0.0, R, "laser", None), (1.05, 0.0, R, "camera", red)])
    assert track.appearance == red and track.appearance_t == 0.1     # fused with the legs
    (track,) = tracker.update(0.2, [(1.0, 0.0, R, "laser")])
    assert track.appearance == red and track.appearance_t == 0.1     # legs tell no look
    (track,) = tracker.update(0.3, [(1.0, 0.0, R, "camera", blue)])
    assert track.appearance == blue and track.appearance_t == 0.3
    (other,) = PeopleTracker().update(0.0, [(1.0, 0.0, R)])
    assert other.appearance is None and other.appearance_t is None


def test_the_lean_filter_steps_bit_for_bit_as_filterpy():
    """`LeanKalmanFilter` leaves out filterpy's copies, not its arithmetic."""
    from skills.people import motion_model
    from skills.people.kalman import KalmanFilter, LeanKalmanFilter
    from skills.people.tracker import inverse_2x2_single
    rng = np.random.default_rng(4)
    filters = []
    for cls in (KalmanFilter, LeanKalmanFilter):
        kf = cls(dim_x=4, dim_z=2)
        kf.x, kf.P = np.array([[1.0], [2.0], [0.3], [-0.1]]), np.diag([0.04, 0.04, 1.0, 1.0])
        kf.H, kf.inv = motion_model.H, inverse_2x2_single
        filters.append(kf)
    for _ in range(50):
        dt = float(rng.uniform(0.05, 0.3))
        z = rng.normal([[1.0], [2.0]], 0.3)
        r = np.diag(rng.uniform(0.001, 0.05, 2))
        for kf in filters:
            kf.predict(F=motion_model.transition(dt), Q=motion_model.process_noise(dt, 0.5))
            kf.update(z, R=r, H=motion_model.H)
        assert filters[0].x.tobytes() == filters[1].x.tobytes()
        assert filters[0].P.tobytes() == filters[1].P.tobytes()


def test_the_stacked_filter_steps_bit_for_bit_as_each_filter_alone():
    """`predict_all` and `update_all` give every filter the floats of its own
    `predict` and `update` (the tracker steps its constant-velocity filters so)."""
    from skills.people import motion_model
    from skills.people.kalman import LeanKalmanFilter, predict_all, update_all
    from skills.people.tracker import _inverses, inverse_2x2_single
    rng = np.random.default_rng(5)

    def filters():
        made = []
        for k in range(6):
            kf = LeanKalmanFilter(dim_x=4, dim_z=2)
            kf.x = np.array([[1.0 + k], [2.0 - k], [0.3], [-0.1 * k]])
            kf.P = np.diag([0.04, 0.05, 1.0, 0.9]) * (1 + k)
            kf.H, kf.inv = motion_model.H, inverse_2x2_single
            made.append(kf)
        return made
    alone, stacked = filters(), filters()
    for _ in range(40):
        dt = float(rng.uniform(0.05, 0.3))
        f, q = motion_model.transition(dt), motion_model.process_noise(dt, 0.5)
        z = rng.normal(2.0, 1.0, (6, 2, 1))
        r = np.array([np.diag(rng.uniform(0.001, 0.05, 2)) for _ in range(6)])
        r[:, 0, 1] = r[:, 1, 0] = rng.uniform(-0.0005, 0.0005, 6)
        for kf in alone:
            kf.predict(F=f, Q=q)
        predict_all(stacked, f, q)
        some = sorted(rng.choice(6, size=int(rng.integers(1, 7)), replace=False).tolist())
        for i in some:
            alone[i].update(z[i], R=r[i], H=motion_model.H)
        update_all([stacked[i] for i in some], z[some], r[some], motion_model.H, _inverses)
        for a, b in zip(alone, stacked):
            assert a.x.tobytes() == b.x.tobytes()
            assert a.P.tobytes() == b.P.tobytes()


def test_a_lost_track_does_not_take_over_someone_farther_than_its_person_can_have_got():
    # bench_follow lookalike seed 2, PERSES: a look-alike's track, standing still and unseen
    # for 1.1 s, took the customer's legs 1.8 m away (its 99.99 % gate spanned about 3 m);
    # the follower then counted the customer a stranger and took the look-alike for her
    tracker = PeopleTracker()
    for k in range(10):                                   # A stands at (2, 0), seen for 1 s
        tracker.update(k * 0.1, [(2.0, 0.0, R)])
    (a,) = tracker.tracks()
    for k in range(10, 21):                               # A is hidden for 1.1 s ...
        tracker.update(k * 0.1, [])
    tracks = tracker.update(2.1, [(2.0, 1.8, R)])         # ... and someone turns up 1.8 m off
    mine = next(t for t in tracks if t.id == a.id)
    assert (mine.x, mine.y) == pytest.approx((2.0, 0.0), abs=0.05) and mine.status == LOST
    assert any(t.id != a.id and t.y == pytest.approx(1.8) for t in tracks)
    # a person hidden for as long who comes back where they may have got is still theirs
    tracker = PeopleTracker()
    for k in range(10):
        tracker.update(k * 0.1, [(2.0, 0.0, R)])
    for k in range(10, 21):
        tracker.update(k * 0.1, [])
    tracks = tracker.update(2.1, [(2.0, 0.9, R)])
    assert [t.id for t in tracks] == [a.id] and tracks[0].status == CONFIRMED


def test_a_standing_person_whose_noise_looked_like_walking_keeps_one_track():
    # The detections of the property test's n=1, seed=1567 (found by a CI run of the test):
    # the filter learns 0.75 m/s from noise by the fifth frame; its prediction then leaves
    # the 99.99 % gate frame after frame while a second track starts on the same person.
    xs = [0.051, 0.016, -0.055, 0.010, -0.243, 0.123, -0.012, 0.015, 0.013, -0.057,
          0.020, -0.031, 0.044, 0.002, -0.018]
    ys = [1.258, 1.299, 1.178, 1.232, 1.168, 1.223, 1.287, 1.226, 1.299, 1.160,
          1.231, 1.205, 1.247, 1.219, 1.190]
    tracker = PeopleTracker()
    for k, (x, y) in enumerate(zip(xs, ys)):
        tracks = tracker.update(k * 0.1, [(x, y, R)])
        assert [t.id for t in tracks] == [1], f"frame {k}: {tracks}"
    assert (tracks[0].x, tracks[0].y) == pytest.approx((0.0, 1.22), abs=0.08)
    assert tracks[0].status == CONFIRMED


def test_a_leftover_detection_goes_to_a_leftover_track_only_within_reach():
    # A stands at the origin, seen for a second; then her track's position is moved `offset`
    # off, out of her gate, as a walking pace learnt from noise carries a prediction off
    def tracker_with_a_track_off_by(offset):
        tracker = PeopleTracker()
        for k in range(10):
            tracker.update(k * 0.1, [(0.0, 0.0, R)])
        tracker._tracks[0].kf.x[0, 0] = offset
        return tracker
    near = tracker_with_a_track_off_by(0.45)                 # out of the gate, within 0.5 m
    assert [t.id for t in near.update(1.0, [(0.0, 0.0, R)])] == [1]
    far = tracker_with_a_track_off_by(0.6)                   # out of the gate and of reach
    assert sorted(t.id for t in far.update(1.0, [(0.0, 0.0, R)])) == [1, 2]
    hidden = tracker_with_a_track_off_by(0.0)                # unseen one frame: left to its
    sure = hidden._tracks[0].kf.P.copy()                     # gate (someone hidden is not
    hidden.update(1.0, [])                                   # re-found by distance alone),
    hidden._tracks[0].kf.x[0, 0] = 0.45                      # here as sure of the place as
    hidden._tracks[0].kf.P = sure                            # when last seen, so out of it
    assert sorted(t.id for t in hidden.update(1.1, [(0.0, 0.0, R)])) == [1, 2]
    off = PeopleTracker(TrackerParams(leftover_reach=0.0))   # the pairing can be turned off
    for k in range(10):
        off.update(k * 0.1, [(0.0, 0.0, R)])
    off._tracks[0].kf.x[0, 0] = 0.45
    assert sorted(t.id for t in off.update(1.0, [(0.0, 0.0, R)])) == [1, 2]


def test_a_leftover_detection_near_two_tracks_starts_a_track_of_its_own():
    # A stands at the origin and B at (0.6, 0); A's prediction is carried to (0, 0.45), out
    # of her gate, her detection is missed, and a detection turns up 0.36 m from A's and
    # 0.43 m from B's prediction: it may be either's, so neither takes it
    tracker = PeopleTracker()
    for k in range(10):
        tracker.update(k * 0.1, [(0.0, 0.0, R), (0.6, 0.0, R)])
    a, b = sorted(tracker.tracks(), key=lambda t: t.x)
    next(s for s in tracker._tracks if s.id == a.id).kf.x[1, 0] = 0.45
    tracks = tracker.update(1.0, [(0.35, 0.35, R), (0.6, 0.0, R)])
    assert len(tracks) == 3
    assert {t.id: (t.x, t.y) for t in tracks}[a.id] == pytest.approx((0.0, 0.45), abs=0.02)
    assert {t.id: t.x for t in tracks}[b.id] == pytest.approx(0.6, abs=0.02)


def test_a_leftover_pairing_never_takes_a_detection_another_track_took():
    # A and B stand 0.45 m apart; B's detection is B's even though it is within 0.5 m of
    # A's prediction when A's own detection is missing
    tracker = PeopleTracker()
    for k in range(10):
        tracker.update(k * 0.1, [(0.0, 0.0, R), (0.45, 0.0, R)])
    a, b = sorted(tracker.tracks(), key=lambda t: t.x)
    tracks = tracker.update(1.0, [(0.45, 0.0, R)])
    assert {t.id: t.x for t in tracks}[b.id] == pytest.approx(0.45, abs=0.02)
    assert {t.id: t.x for t in tracks}[a.id] == pytest.approx(0.0, abs=0.02)
