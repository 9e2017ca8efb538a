"""Same-frame fusion, the robot-to-world transform and the vectorised association."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from skills.people import robot_to_world
from skills.people.association import (INFEASIBLE, assign, gated_cost, mahalanobis_sq,
                                       unambiguous_pairs)
from skills.people.fusion import fuse_close_detections


def test_camera_and_laser_detections_fuse_by_information():
    xy = np.array([[1.0, 0.0], [1.1, 0.0], [3.0, 0.0]])
    cov = np.array([np.eye(2) * 0.05 ** 2, np.eye(2) * 0.1 ** 2, np.eye(2) * 0.05 ** 2])
    fused_xy, fused_cov, flags = fuse_close_detections(xy, cov, 0.3, np.array([True, False, True]))
    # The fused pair first (it holds the first detection), then the far one: weights
    # 1/0.0025 = 400 and 1/0.01 = 100, so x = (400 * 1.0 + 100 * 1.1) / 500 = 1.02 and the
    # variance is 1 / 500 = 0.002.
    assert fused_xy == pytest.approx(np.array([[1.02, 0.0], [3.0, 0.0]]))
    assert fused_cov[0] == pytest.approx(np.eye(2) * 0.002)
    assert fused_cov[1] == pytest.approx(np.eye(2) * 0.0025)
    assert flags.tolist() == [True, True]


def test_a_chain_of_close_detections_is_one_cluster_and_order_is_kept():
    xy = np.array([[5.0, 5.0], [0.0, 0.0], [0.2, 0.0], [0.4, 0.0], [9.0, 9.0]])
    cov = np.array([np.eye(2) * 0.01] * 5)
    fused_xy, fused_cov, flags = fuse_close_detections(xy, cov, 0.3,
                                                       np.array([False, False, True, False, False]))
    assert fused_xy == pytest.approx(np.array([[5.0, 5.0], [0.2, 0.0], [9.0, 9.0]]))
    assert fused_cov[1] == pytest.approx(np.eye(2) * 0.01 / 3)
    assert flags.tolist() == [False, True, False]


def test_detections_farther_apart_than_the_merge_distance_stay_apart():
    xy = np.array([[0.0, 0.0], [0.5, 0.0]])
    cov = np.array([np.eye(2) * 0.01] * 2)
    out_xy, out_cov, _ = fuse_close_detections(xy, cov, 0.3)
    assert out_xy is xy and out_cov is cov


def test_robot_to_world_rotates_position_and_covariance():
    cov = np.diag([0.04, 0.01])                       # long along the robot's x axis
    x, y, world_cov = robot_to_world(2.0, 0.0, cov, (1.0, 1.0, math.pi / 2))
    assert (x, y) == pytest.approx((1.0, 3.0))        # robot faces +y: 2 m ahead is +2 in y
    assert world_cov == pytest.approx(np.diag([0.01, 0.04]))
    _, _, inflated = robot_to_world(2.0, 0.0, cov, (0.0, 0.0, 0.0), pose_sigma=0.1)
    assert inflated == pytest.approx(np.diag([0.05, 0.02]))


def test_mahalanobis_distance_matches_a_hand_computation():
    track_xy = np.array([[0.0, 0.0]])
    track_cov = np.array([[[0.03, 0.0], [0.0, 0.07]]])
    det_xy = np.array([[0.2, 0.3]])
    det_cov = np.array([np.eye(2) * 0.01])
    d2, log_det = mahalanobis_sq(track_xy, track_cov, det_xy, det_cov)
    # S = diag(0.04, 0.08): d^2 = 0.2^2 / 0.04 + 0.3^2 / 0.08 = 1 + 1.125.
    assert d2[0, 0] == pytest.approx(2.125)
    assert log_det[0, 0] == pytest.approx(math.log(0.04 * 0.08))


def test_assignment_is_global_and_respects_the_gate():
    # Greedy would give detection 0 to track 0 (cost 1) and leave track 1 with cost 10;
    # the global optimum pairs 0-1 and 1-0 (2 + 2). Track 2 has nothing in its gate.
    cost = np.array([[1.0, 2.0], [2.0, 10.0], [INFEASIBLE, INFEASIBLE]])
    pairs, lonely_tracks, lonely_dets = assign(cost)
    assert sorted(pairs) == [(0, 1), (1, 0)] and lonely_tracks == [2] and lonely_dets == []
    gated = gated_cost(np.array([[1.0, 30.0]]), np.zeros((1, 2)), gate=18.4)
    assert gated[0, 1] == INFEASIBLE


def test_only_unambiguous_pairs_within_the_limit_are_made():
    tracks = np.array([[0.0, 0.0], [1.0, 0.0], [5.0, 0.0]])
    dets = np.array([[0.6, 0.0], [1.3, 0.0], [5.3, 0.0]])
    # detection 0 is within 0.65 m of tracks 0 and 1, and track 1 has detections 0 and 1:
    # only track 2 and detection 2 have each other alone
    assert unambiguous_pairs(tracks, dets, limit=0.65) == [(2, 2)]
    # within 0.35 m, track 1 and detection 1 have each other alone as well
    assert unambiguous_pairs(tracks, dets, limit=0.35) == [(1, 1), (2, 2)]
    assert unambiguous_pairs(tracks[:0], dets, limit=1.0) == []


@settings(max_examples=40, deadline=None)
@given(n=st.integers(0, 12), seed=st.integers(0, 10_000))
def test_fusion_never_merges_people_standing_apart(n, seed):
    rng = np.random.default_rng(seed)
    xy = np.column_stack((np.arange(n) * 0.6, rng.uniform(-0.05, 0.05, n)))
    cov = np.array([np.eye(2) * 0.0025] * n).reshape(n, 2, 2)
    out_xy, _, _ = fuse_close_detections(xy, cov, 0.3)
    assert len(out_xy) == n
