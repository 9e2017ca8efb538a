"""Robot frame to world frame for detections: the tracker's ego-motion compensation.

The tracker works in the world frame, so a robot that drives or turns does not make still
people appear to move. The skill moves every detection into the world frame with the robot's
pose of the same tick before handing it to the tracker.
"""
from __future__ import annotations

import math

import numpy as np


def robot_to_world(x: float, y: float, cov, pose: tuple[float, float, float],
                   pose_sigma: float = 0.0) -> tuple[float, float, np.ndarray]:
    """Rotate and shift (x, y) by the robot pose (px, py, heading); rotate the covariance
    the same way (R C R^T) and add `pose_sigma`^2 for the pose's own uncertainty."""
    px, py, th = pose
    c, s = math.cos(th), math.sin(th)
    rot = np.array([[c, -s], [s, c]])
    world_cov = rot @ np.asarray(cov, dtype=float) @ rot.T
    if pose_sigma:
        world_cov = world_cov + np.eye(2) * pose_sigma ** 2
    return px + c * x - s * y, py + s * x + c * y, world_cov


def detections_to_world(detections, pose: tuple[float, float, float]) -> list[tuple]:
    """(x, y, world covariance, source, appearance) of each detection (robots.devices.Detection)
    in the world frame: `robot_to_world`'s floats, with the rotation made once for the tick and
    each covariance object rotated once (a detector hands all its detections the same one).
    Detections with the same covariance object share one read-only array."""
    if not detections:
        return []
    px, py, th = pose
    c, s = math.cos(th), math.sin(th)
    rot = np.array([[c, -s], [s, c]])
    rotated: dict[int, np.ndarray] = {}
    world = []
    for d in detections:
        world_cov = rotated.get(id(d.cov))
        if world_cov is None:
            world_cov = rotated[id(d.cov)] = rot @ np.asarray(d.cov, dtype=float) @ rot.T
            world_cov.flags.writeable = False
        world.append((px + c * d.x - s * d.y, py + s * d.x + c * d.y, world_cov, d.source,
                      d.appearance))
    return world
