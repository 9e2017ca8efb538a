"""The camera's calibration: pinhole intrinsics (and lens distortion) that turn pixels into bearings.

From the robot profile ([camera] hfov_deg with the image size: a centred pinhole without
distortion) or from a calibration file as OpenCV's calibration tools write it (YAML or XML with
camera_matrix, distortion_coefficients, image_width, image_height).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from robots.exceptions import ProfileError


@dataclass(frozen=True)
class Intrinsics:
    fx: float                # px
    fy: float
    cx: float
    cy: float
    width: int
    height: int
    distortion: tuple[float, ...] = field(default=())   # OpenCV's k1 k2 p1 p2 [k3 ...]

    @classmethod
    def from_fov(cls, hfov_deg: float, width: int, height: int) -> "Intrinsics":
        """A centred pinhole with square pixels and this horizontal field of view."""
        f = (width / 2) / math.tan(math.radians(hfov_deg) / 2)
        return cls(f, f, width / 2, height / 2, width, height)

    def scaled_to(self, width: int, height: int) -> "Intrinsics":
        """The same lens at another image size (a camera delivering a different resolution)."""
        if (width, height) == (self.width, self.height):
            return self
        sx, sy = width / self.width, height / self.height
        return Intrinsics(self.fx * sx, self.fy * sy, self.cx * sx, self.cy * sy, width, height,
                          self.distortion)

    def normalized(self, u: float, v: float) -> tuple[float, float]:
        """The undistorted normalized image point (x/z, y/z) of pixel (u, v)."""
        if not any(self.distortion):
            return (u - self.cx) / self.fx, (v - self.cy) / self.fy
        import cv2
        matrix = np.array([[self.fx, 0, self.cx], [0, self.fy, self.cy], [0, 0, 1]], float)
        point = cv2.undistortPoints(np.array([[[u, v]]], float), matrix,
                                    np.array(self.distortion, float))
        return float(point[0, 0, 0]), float(point[0, 0, 1])

    def bearing(self, u: float, v: float | None = None) -> float:
        """rad, left positive (the robot's convention): pixel columns right of centre are negative."""
        x, _ = self.normalized(u, self.cy if v is None else v)
        return -math.atan(x)


def load_calibration(path: str | Path) -> Intrinsics:
    """Intrinsics from an OpenCV calibration file; ProfileError naming the file and the key."""
    import cv2
    path = Path(path)
    if not path.exists():
        raise ProfileError(f"{path}: camera calibration file not found")
    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    try:
        if not storage.isOpened():
            raise ProfileError(f"{path}: not an OpenCV calibration file (YAML or XML)")
        matrix = storage.getNode("camera_matrix").mat()
        if matrix is None or matrix.shape != (3, 3):
            raise ProfileError(f"{path}: camera_matrix missing or not 3x3")
        dist = storage.getNode("distortion_coefficients").mat()
        width = int(storage.getNode("image_width").real())
        height = int(storage.getNode("image_height").real())
    finally:
        storage.release()
    if width <= 0 or height <= 0:
        raise ProfileError(f"{path}: image_width and image_height must be positive "
                           f"(got {width} x {height})")
    distortion = () if dist is None else tuple(float(v) for v in np.ravel(dist))
    return Intrinsics(float(matrix[0, 0]), float(matrix[1, 1]), float(matrix[0, 2]),
                      float(matrix[1, 2]), width, height, distortion)
