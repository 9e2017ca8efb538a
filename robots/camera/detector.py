"""The camera as a `PersonDetector`: boxes found in the newest frame, turned into robot-frame
positions with the calibration, so the people tracker gets them as it gets the simulated
camera's.

A box's centre column gives the bearing (through the lens model, plus the camera's mounting
heading and, for a camera on the pan-tilt head, the head's pan as the head reports it); its
height gives a rough range (a person of `person_height` fills BODY_SHARE of a body box; a face
box spans `face_size`). The covariance is the bearing's and the range's uncertainty turned into
x, y. Each detection carries the colour histogram of the box's torso (8 hue bins, as the
simulated camera's), so followers can tell people apart.
"""
from __future__ import annotations

import math
import threading
from pathlib import Path

import numpy as np

from robots.camera.finder import BODY_SHARE, Box, PeopleFinder
from robots.camera.intrinsics import Intrinsics, load_calibration
from robots.camera.source import FrameSource
from robots.devices import Detection, PanTiltHead, PersonDetector
from robots.profile import CameraSpec

HUE_BINS = 8


class CameraPersonDetector(PersonDetector):
    """People in a `FrameSource`'s newest frame; each frame is reported once (later calls
    before a new frame return []).

    In real time the finding runs on a thread of its own (a HOG search can take longer than a
    tick), and `detect` hands over what it found since the last call;
    on a simulated clock `detect` finds them itself, so a run stays deterministic."""

    def __init__(self, source: FrameSource, spec: CameraSpec, intrinsics: Intrinsics,
                 finder: PeopleFinder | None = None, head: PanTiltHead | None = None,
                 threaded: bool | None = None) -> None:
        self.source = source
        self.spec = spec
        self.intrinsics = intrinsics
        self.finder = finder or PeopleFinder(spec.detect)
        self.head = head if spec.on_head else None
        simulated = getattr(getattr(source, "clock", None), "simulated", False)
        self.threaded = not simulated if threaded is None else threaded
        self._last_number = 0
        self.boxes: list[Box] = []          # the newest frame's boxes (for display, tests)
        self._found: list[Detection] = []   # threaded: found since the last detect()
        self._lock = threading.Lock()
        self._closing = threading.Event()
        self._worker: threading.Thread | None = None

    @classmethod
    def for_profile(cls, profile, device: str | None = None, clock=None,
                    head: PanTiltHead | None = None, **source_options) -> "CameraPersonDetector":
        """The profile's [camera] at `device` (default its own `device`), not yet opened."""
        spec = profile.camera
        if spec is None:
            raise ValueError(f"robot '{profile.name}' has no [camera] in its profile")
        source = FrameSource(device or spec.device, clock=clock, **source_options)
        return cls(source, spec, intrinsics_for(spec, Path(profile.source).parent), head=head)

    def open(self) -> None:
        self.source.open()
        if self.threaded:
            self._closing.clear()
            self._worker = threading.Thread(target=self._find_in_background,
                                            name="camera-finder", daemon=True)
            self._worker.start()

    def close(self) -> None:
        self._closing.set()
        if self._worker is not None and self._worker is not threading.current_thread():
            self._worker.join(timeout=2.0)
        self._worker = None
        self.source.close()

    def fault(self) -> str | None:
        return self.source.fault()

    def detect(self) -> list[Detection]:
        if self.threaded:
            with self._lock:
                found, self._found = self._found, []
            return found
        return self._find_in_newest()

    def _find_in_background(self) -> None:
        while not self._closing.is_set():
            found = self._find_in_newest()
            if found:
                with self._lock:
                    self._found = found          # only the newest frame's: older ones are stale
            elif self._closing.wait(0.01):
                return

    def _find_in_newest(self) -> list[Detection]:
        frame = self.source.read()
        if frame is None or frame.number == self._last_number:
            return []
        self._last_number = frame.number
        image = frame.image
        lens = self.intrinsics.scaled_to(image.shape[1], image.shape[0])
        pan = self.head.read()[0] if self.head is not None else 0.0
        self.boxes = self.finder.find(image)
        out = []
        for box in self.boxes:
            detection = self._locate(box, lens, pan, frame.t, image)
            if detection is not None:
                out.append(detection)
        return out

    def _locate(self, box: Box, lens: Intrinsics, pan: float, t: float,
                image: np.ndarray) -> Detection | None:
        spec = self.spec
        u, v = box.centre
        bearing = lens.bearing(u, v)
        size = spec.person_height / BODY_SHARE if box.kind == "body" else spec.face_size
        depth = lens.fy * size / max(box.h, 1)
        distance = depth / max(math.cos(bearing), 1e-3)
        if distance > spec.max_range:
            return None
        heading = spec.heading + pan + bearing
        x = spec.x + distance * math.cos(heading)
        y = spec.y + distance * math.sin(heading)
        return Detection(t, x, y, covariance(distance, heading, spec), "camera",
                         torso_histogram(image, box))


def intrinsics_for(spec: CameraSpec, folder: Path) -> Intrinsics:
    """The calibration file's intrinsics if the profile names one, else a pinhole from hfov."""
    if spec.calibration:
        path = Path(spec.calibration)
        return load_calibration(path if path.is_absolute() else folder / path)
    return Intrinsics.from_fov(spec.hfov_deg, spec.width, spec.height)


def covariance(distance: float, heading: float, spec: CameraSpec):
    """x, y covariance of a detection: range error along the ray, bearing error across it."""
    radial = (spec.range_sd * distance) ** 2
    lateral = (spec.bearing_sd * distance) ** 2
    c, s = math.cos(heading), math.sin(heading)
    xx = c * c * radial + s * s * lateral
    yy = s * s * radial + c * c * lateral
    xy = c * s * (radial - lateral)
    return ((xx, xy), (xy, yy))


def torso_histogram(image: np.ndarray, box: Box) -> tuple[float, ...] | None:
    """A normalised hue histogram of the clothing: a body box's middle, below a face box."""
    import cv2
    if box.kind == "body":
        top, bottom = box.y + box.h * 0.3, box.y + box.h * 0.55
        left, right = box.x + box.w * 0.3, box.x + box.w * 0.7
    else:
        top, bottom = box.y + box.h * 1.3, box.y + box.h * 2.3
        left, right = box.x, box.x + box.w
    rows = slice(max(0, int(top)), min(image.shape[0], int(bottom)))
    cols = slice(max(0, int(left)), min(image.shape[1], int(right)))
    patch = image[rows, cols]
    if patch.size == 0:
        return None
    hsv = cv2.cvtColor(patch, cv2.COLOR_BGR2HSV)
    hist = cv2.calcHist([hsv], [0], None, [HUE_BINS], [0, 180]).ravel() + 1e-6
    return tuple(float(v) for v in hist / hist.sum())
