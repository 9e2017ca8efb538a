"""Frames from a camera through OpenCV's `cv2.VideoCapture`: a device index ("0"), a V4L2 path
("/dev/video0"), a stream URL (rtsp://, http://) or a video file.

A live camera is read by a thread of its own (so the newest frame is always at hand and the
driver's buffer never fills); a video file is played at its own frame rate on the given clock
(a simulated clock plays it frame by frame, deterministically), once or in a loop.
A camera that delivers nothing for STALE s, or cannot be opened again, is a fault (`fault()`),
re-opened with back-off; a file that ended is a fault too (the camera sees nothing any more).
"""
from __future__ import annotations

import logging
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robots.exceptions import LinkError
from robots.link.backoff import Backoff

log = logging.getLogger(__name__)

STALE = 1.0            # s without a frame from a live camera -> fault
STREAMS = ("rtsp://", "rtsps://", "http://", "https://", "udp://", "tcp://")


@dataclass(frozen=True)
class Frame:
    t: float               # robot time it was taken
    number: int            # counts up by one per frame delivered
    image: np.ndarray      # BGR


def capture_target(address: str) -> int | str:
    """What VideoCapture opens for an address: a device index for digits, else the text."""
    text = address.strip()
    return int(text) if text.isdigit() else text


def is_file(address: str) -> bool:
    text = address.strip()
    return not text.isdigit() and not text.startswith(STREAMS) and not text.startswith("/dev/")


class FrameSource:
    """The newest frame of one camera or video (see the module docstring). Options: fps (a
    file's playback rate; default the file's own), loop (replay a file from the start)."""

    def __init__(self, address: str, clock=None, fps: float | None = None,
                 loop: bool = False) -> None:
        import cv2
        self._cv2 = cv2
        self.address = str(address)
        self.clock = clock
        self.loop = loop
        self.file = is_file(self.address)
        self.fps = fps
        self.frames = 0
        self.last_error = ""
        self._capture = None
        self._newest: Frame | None = None
        self._lock = threading.Lock()
        self._closing = threading.Event()
        self._thread: threading.Thread | None = None
        self._backoff = Backoff(initial=0.2, factor=2.0, maximum=2.0)
        self._last_frame_time = time.monotonic()
        self._t0 = 0.0
        self._played = 0           # frames of the file consumed so far
        self._ended = False

    # -- time ------------------------------------------------------------------------------------
    def _now(self) -> float:
        return self.clock.now() if self.clock is not None else time.monotonic()

    # -- opening -----------------------------------------------------------------------------------
    def open(self) -> None:
        """Open the camera or file; LinkError saying what the address should be if it fails."""
        self._capture = self._open_capture()
        if self.file:
            self.fps = self.fps or self._capture.get(self._cv2.CAP_PROP_FPS) or 10.0
            self._t0 = self._now()
            return
        self._closing.clear()
        self._thread = threading.Thread(target=self._read_live, name="camera-reader",
                                        daemon=True)
        self._thread.start()

    def _open_capture(self):
        if self.file and not Path(self.address).exists():
            raise LinkError(f"camera {self.address!r}: no such video file (a camera is a device "
                            f"index such as 0, a /dev/video path, an rtsp:// or http:// URL or a "
                            f"video file)")
        capture = self._cv2.VideoCapture(capture_target(self.address))
        if not capture.isOpened():
            capture.release()
            raise LinkError(f"camera {self.address!r}: OpenCV cannot open it (a camera is a "
                            f"device index such as 0, a /dev/video path, an rtsp:// or http:// "
                            f"URL or a video file)")
        return capture

    # -- reading -----------------------------------------------------------------------------------
    def read(self) -> Frame | None:
        """The newest frame (None before the first one, or after the end of a file)."""
        if self.file:
            return self._read_file()
        with self._lock:
            return self._newest

    def _read_file(self) -> Frame | None:
        """The frame due now at the file's rate, skipping those whose time has passed."""
        if self._capture is None or self._ended:
            return self._newest if not self._ended else None
        due = int((self._now() - self._t0) * self.fps + 1e-9) + 1    # frames shown by now
        while self._played < due:
            ok, image = self._capture.read()
            if not ok:
                if self.loop and self._played:
                    self._capture.set(self._cv2.CAP_PROP_POS_FRAMES, 0)
                    self._t0, self._played, due = self._now(), 0, 1
                    continue
                self._ended = True
                self.last_error = (f"camera {self.address!r}: the video ended after "
                                   f"{self.frames} frames")
                return None
            self._played += 1
            if self._played == due:
                self.frames += 1
                self._newest = Frame(self._now(), self.frames, image)
        return self._newest

    def _read_live(self) -> None:
        while not self._closing.is_set():
            capture = self._capture
            ok, image = (False, None) if capture is None else capture.read()
            if ok:
                with self._lock:
                    self.frames += 1
                    self._newest = Frame(self._now(), self.frames, image)
                self._last_frame_time = time.monotonic()
                self._backoff.reset()
                continue
            if time.monotonic() - self._last_frame_time > STALE:
                self._reopen()
            else:
                self._closing.wait(0.01)

    def _reopen(self) -> None:
        silent = time.monotonic() - self._last_frame_time
        self.last_error = f"camera {self.address!r}: no frame for {silent:.1f} s"
        if self._capture is not None:
            log.warning("%s", self.last_error)
            self._capture.release()
            self._capture = None
        if self._closing.wait(self._backoff.next_delay()):
            return
        try:
            self._capture = self._open_capture()
        except LinkError as exc:
            self.last_error = f"{self.last_error}; {exc}"

    # -- state -----------------------------------------------------------------------------------
    def fault(self) -> str | None:
        """Why no fresh frames come, or None."""
        if self.file:
            return self.last_error if self._ended else None
        if time.monotonic() - self._last_frame_time > STALE:
            return self.last_error or f"camera {self.address!r}: no frame for {STALE:g} s"
        return None

    def close(self) -> None:
        self._closing.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=2.0)
        self._thread = None
        if self._capture is not None:
            self._capture.release()
            self._capture = None
