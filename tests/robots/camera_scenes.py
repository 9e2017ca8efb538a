"""Pictures the tests draw themselves: a person (head, torso, arms, legs) and a face, placed in
a camera image where a person at a given distance and bearing would appear."""
from __future__ import annotations

import math

import numpy as np

from robots.camera.intrinsics import Intrinsics

BACKGROUND = 200


def blank(lens: Intrinsics) -> np.ndarray:
    return np.full((lens.height, lens.width, 3), BACKGROUND, np.uint8)


def draw_person(image: np.ndarray, cx: float, top: float, height: float,
                shirt=(40, 40, 160), dark=(40, 40, 40)) -> None:
    """A standing person `height` px tall, centred on column `cx`, head at row `top`."""
    import cv2
    u = height / 8.0                          # eight head-heights
    cv2.ellipse(image, (int(cx), int(top + 0.5 * u)), (int(0.38 * u), int(0.5 * u)), 0, 0, 360,
                dark, -1)
    cv2.rectangle(image, (int(cx - 0.15 * u), int(top + 0.9 * u)),
                  (int(cx + 0.15 * u), int(top + 1.2 * u)), dark, -1)
    torso = [[cx - u, top + 1.2 * u], [cx + u, top + 1.2 * u], [cx + 0.8 * u, top + 4 * u],
             [cx - 0.8 * u, top + 4 * u]]
    cv2.fillPoly(image, [np.array(torso, np.int32)], shirt)
    for s in (-1, 1):
        arm = [[cx + s * u, top + 1.25 * u], [cx + s * 1.35 * u, top + 1.4 * u],
               [cx + s * 1.25 * u, top + 4.2 * u], [cx + s * 0.95 * u, top + 4.2 * u]]
        leg = [[cx + s * 0.05 * u, top + 4 * u], [cx + s * 0.8 * u, top + 4 * u],
               [cx + s * 0.7 * u, top + 8 * u], [cx + s * 0.2 * u, top + 8 * u]]
        cv2.fillPoly(image, [np.array(arm, np.int32)], shirt)
        cv2.fillPoly(image, [np.array(leg, np.int32)], dark)


def draw_face(image: np.ndarray, cx: int, cy: int, width: int, skin=(150, 170, 205)) -> None:
    """A frontal face `width` px wide: skin, hair, brows, eyes, nose shadow, mouth."""
    import cv2
    s = width
    cv2.ellipse(image, (cx, cy), (int(s * 0.5), int(s * 0.65)), 0, 0, 360, skin, -1)
    for side in (-1, 1):
        ex, ey = int(cx + side * s * 0.2), int(cy - s * 0.12)
        cv2.ellipse(image, (ex, int(ey - s * 0.1)), (int(s * 0.14), int(s * 0.03)), 0, 0, 360,
                    (50, 50, 60), -1)
        cv2.ellipse(image, (ex, ey), (int(s * 0.1), int(s * 0.05)), 0, 0, 360, (90, 90, 100), -1)
        cv2.circle(image, (ex, ey), int(s * 0.035), (20, 20, 20), -1)
    cv2.ellipse(image, (cx, int(cy + s * 0.12)), (int(s * 0.08), int(s * 0.04)), 0, 0, 360,
                (110, 125, 160), -1)
    cv2.ellipse(image, (cx, int(cy + s * 0.3)), (int(s * 0.17), int(s * 0.04)), 0, 0, 360,
                (70, 70, 140), -1)
    cv2.ellipse(image, (cx, int(cy - s * 0.45)), (int(s * 0.52), int(s * 0.28)), 0, 180, 360,
                (30, 30, 40), -1)


def person_at(image: np.ndarray, lens: Intrinsics, distance: float, bearing: float,
              height_m: float = 1.7, **colours) -> None:
    """Draw a person standing `distance` m away at `bearing` rad (left positive), the camera at
    half their height."""
    depth = distance * math.cos(bearing)
    height = lens.fy * height_m / depth
    column = lens.cx - lens.fx * math.tan(bearing)
    draw_person(image, column, lens.cy - height / 2, height, **colours)


def smooth(image: np.ndarray) -> np.ndarray:
    """A camera's slight blur (hard drawn edges are not what a lens delivers)."""
    import cv2
    return cv2.GaussianBlur(image, (3, 3), 0)
