"""Pictures of people for a camera that looks at the simulated world (and for tests): a standing
person drawn as head, torso, arms and legs, at the place in the image where a person at a given
distance and bearing appears through a pinhole lens.

The drawing is plain (flat colours on a light background, a slight blur for the lens), yet it
has what OpenCV's HOG people detector looks for; a person close enough for the face to be 40 px
tall gets a frontal face (skin, brows, eyes, nose, mouth, hair) that its face cascade finds.
The shirt has the hue of the person's strongest appearance bin, so a camera's torso histogram
tells people apart as the simulated detector's appearance does.
"""
from __future__ import annotations

import math

import numpy as np

from robots.camera.intrinsics import Intrinsics

BACKGROUND = 200
DARK = (40, 40, 40)
FACE_FROM = 40          # px: a head at least this tall is drawn as a face


def blank(lens: Intrinsics) -> np.ndarray:
    return np.full((lens.height, lens.width, 3), BACKGROUND, np.uint8)


def smooth(image: np.ndarray) -> np.ndarray:
    """A lens's slight blur (hard drawn edges are not what a camera delivers)."""
    import cv2
    return cv2.GaussianBlur(image, (3, 3), 0)


def draw_person(image: np.ndarray, cx: float, top: float, height: float,
                shirt=(40, 40, 160), dark=DARK) -> None:
    """A standing person `height` px tall, centred on column `cx`, the top of the head at row
    `top` (eight head heights tall)."""
    import cv2
    u = height / 8.0
    head_centre = (int(cx), int(top + 0.5 * u))
    if u >= FACE_FROM:
        draw_face(image, head_centre[0], head_centre[1], int(0.76 * u))
    else:
        cv2.ellipse(image, head_centre, (int(0.38 * u), int(0.5 * u)), 0, 0, 360, dark, -1)
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
    """A frontal face `width` px wide centred at (cx, cy)."""
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


def shirt_colour(appearance) -> tuple[int, int, int]:
    """BGR of the hue bin the appearance histogram weighs most (8 bins over OpenCV's 0..180)."""
    import cv2
    bins = len(appearance)
    hue = int((int(np.argmax(appearance)) + 0.5) * 180 / bins)
    bgr = cv2.cvtColor(np.uint8([[[hue, 200, 190]]]), cv2.COLOR_HSV2BGR)[0, 0]
    return int(bgr[0]), int(bgr[1]), int(bgr[2])


def render(lens: Intrinsics, people) -> np.ndarray:
    """One frame: `people` as (distance m, bearing rad, shirt BGR), nearest drawn last."""
    image = blank(lens)
    for distance, bearing, shirt in sorted(people, key=lambda p: -p[0]):
        if distance * math.cos(bearing) > 0.3:
            person_at(image, lens, distance, bearing, shirt=shirt)
    return smooth(image)
