"""People perception, the pure part: leg detection in laser scans, sonar candidates, same-frame
fusion of detections, a multi-person Kalman tracker (filterpy) and the choice of the
interaction partner.

Nothing here touches the blackboard or a device; `skills.perception` feeds these functions every
tick and writes what they return. See docs/tracking.md for the model and its figures.
"""
from skills.people.frames import robot_to_world
from skills.people.legs import LegParams, detect_legs
from skills.people.sonar import SonarParams, sonar_candidates
from skills.people.track import CONFIRMED, LOST, TENTATIVE, Track
from skills.people.tracker import PeopleTracker, TrackerParams
from skills.people.user import UserSelector, approach_speed, distance

__all__ = [
    "CONFIRMED", "LOST", "TENTATIVE", "LegParams", "PeopleTracker", "SonarParams", "Track",
    "TrackerParams", "UserSelector", "approach_speed", "detect_legs", "distance",
    "robot_to_world", "sonar_candidates",
]
