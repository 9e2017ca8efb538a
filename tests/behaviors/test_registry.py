import pytest

from behaviors import robot_capabilities
from behaviors.exceptions import UnknownBehaviorError, UnsupportedBehaviorError
from behaviors.percepts import percept_specs
from behaviors.percept_view import PerceptTracker
from behaviors.registry import behavior_specs, get_behavior
from behaviors.drawing import render_tree


def test_the_bundled_behaviors_come_from_entry_points():
    assert {"Idle", "FaceUser", "AttractAttention", "Survey", "CallBack"} <= set(behavior_specs())


def test_face_user_turns_the_head_on_horos_and_the_body_on_perses():
    spec = get_behavior("FaceUser")
    assert spec.realization_for(robot_capabilities("horos")).name == "head"
    assert spec.realization_for(robot_capabilities("perses")).name == "body"
    assert "LookAtUser" in render_tree("FaceUser", robot_capabilities("horos"))
    assert "TurnToUser" in render_tree("FaceUser", robot_capabilities("perses"))


def test_a_robot_without_a_touch_screen_cannot_run_the_survey():
    with pytest.raises(UnsupportedBehaviorError, match="touch_screen"):
        get_behavior("Survey").realization_for(frozenset({"base", "speech_out"}))
    assert get_behavior("Survey").requires == frozenset({"touch_screen", "speech_out"})


def test_unknown_behavior_names_the_registered_ones():
    with pytest.raises(UnknownBehaviorError, match="FaceUser"):
        get_behavior("FaceUsr")


def test_the_percept_view_offers_exactly_the_declared_percepts(tmp_path):
    from behaviors.robot import open_robot
    robot = open_robot("horos", fast=True)
    try:
        view = PerceptTracker().view(robot.skills, robot.now())
    finally:
        robot.close()
    assert set(view) == set(percept_specs())
    with pytest.raises(TypeError):
        view["people.count"] = 3      # read-only
