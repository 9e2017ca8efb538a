"""People and faces in an image, found by the detectors OpenCV itself ships (no download).

- body: the HOG people detector (Dalal and Triggs' linear SVM, `HOGDescriptor_getDefaultPeopleDetector`),
  whole upright people from about 100 px tall; its box has the person in about its middle
  three quarters of the height (BODY_SHARE), as the detector was trained;
- face: the frontal-face Haar cascade from `cv2.data.haarcascades`, for people so close that
  only their head and shoulders are in view.

A face inside a body box is the same person and is dropped.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

BODY_SHARE = 0.75            # of a HOG box's height that is the person (96 of 128 px)
FACE_CASCADE = "haarcascade_frontalface_default.xml"
KINDS = ("body", "face")


@dataclass(frozen=True)
class Box:
    kind: str            # "body" or "face"
    x: int               # px, top-left
    y: int
    w: int
    h: int
    score: float = 1.0

    @property
    def centre(self) -> tuple[float, float]:
        return self.x + self.w / 2, self.y + self.h / 2

    def contains(self, u: float, v: float) -> bool:
        return self.x <= u <= self.x + self.w and self.y <= v <= self.y + self.h


class PeopleFinder:
    """Finds `kinds` of boxes in BGR images. `min_score`: the HOG SVM margin a body needs;
    `max_width`: wider images are searched at this width (the HOG search is the costly part;
    a narrower one is faster but misses small, far people: the smallest body it finds is 128
    px tall in the reduced image)."""

    def __init__(self, kinds: tuple[str, ...] = KINDS, min_score: float = 0.5,
                 max_width: int = 480) -> None:
        import cv2
        unknown = set(kinds) - set(KINDS)
        if unknown or not kinds:
            raise ValueError(f"detector kinds {kinds}: allowed a non-empty choice of {KINDS}")
        self.kinds = tuple(kinds)
        self.min_score = float(min_score)
        self.max_width = int(max_width)
        self._cv2 = cv2
        self._hog = None
        self._face = None
        if "body" in kinds:
            self._hog = cv2.HOGDescriptor()
            self._hog.setSVMDetector(cv2.HOGDescriptor_getDefaultPeopleDetector())
        if "face" in kinds:
            self._face = cv2.CascadeClassifier(cv2.data.haarcascades + FACE_CASCADE)
            if self._face.empty():
                raise RuntimeError(f"OpenCV's {FACE_CASCADE} did not load from "
                                   f"{cv2.data.haarcascades}")

    def find(self, image: np.ndarray) -> list[Box]:
        """Boxes in `image`'s pixel coordinates (bodies first)."""
        cv2 = self._cv2
        scale = min(1.0, self.max_width / image.shape[1])
        small = image if scale == 1.0 else cv2.resize(image, None, fx=scale, fy=scale,
                                                      interpolation=cv2.INTER_AREA)
        bodies = self._bodies(small) if self._hog is not None else []
        faces = self._faces(small) if self._face is not None else []
        faces = [f for f in faces if not any(b.contains(*f.centre) for b in bodies)]
        return [_rescaled(box, 1 / scale) for box in bodies + faces]

    def _bodies(self, image: np.ndarray) -> list[Box]:
        rects, weights = self._hog.detectMultiScale(image, winStride=(8, 8), padding=(8, 8),
                                                    scale=1.05)
        return [Box("body", int(x), int(y), int(w), int(h), float(s))
                for (x, y, w, h), s in zip(rects, np.ravel(weights)) if s >= self.min_score]

    def _faces(self, image: np.ndarray) -> list[Box]:
        grey = self._cv2.cvtColor(image, self._cv2.COLOR_BGR2GRAY)
        rects = self._face.detectMultiScale(grey, scaleFactor=1.1, minNeighbors=4,
                                            minSize=(24, 24))
        return [Box("face", int(x), int(y), int(w), int(h)) for x, y, w, h in rects]


def _rescaled(box: Box, factor: float) -> Box:
    if factor == 1.0:
        return box
    return Box(box.kind, round(box.x * factor), round(box.y * factor), round(box.w * factor),
               round(box.h * factor), box.score)
