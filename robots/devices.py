"""Interfaces of the devices around the base: laser, person detector, pan-tilt head, touch screen,
speaker. The simulation implements each of them (`robots.sim.devices`); a real robot would
implement them over its own drivers. Units are SI; angles in radians, robot frame x forward.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class LaserScan:
    t: float                 # robot time of the scan
    angles: np.ndarray       # rad, robot frame, ascending
    ranges: np.ndarray       # m; math.inf where nothing was hit within max_range
    origin: tuple[float, float, float]  # laser pose (x, y, heading) in the robot frame


@dataclass(frozen=True)
class Detection:
    """One person candidate in the robot frame, with its position covariance (m^2).

    `appearance`: what the person looks like, where the sensor can tell (a camera: a
    normalised colour histogram of the clothing, the same length for every detection of one
    detector); None where it cannot (laser legs, sonar)."""
    t: float
    x: float
    y: float
    cov: tuple[tuple[float, float], tuple[float, float]]
    source: str = "camera"
    appearance: tuple[float, ...] | None = None


class Laser(ABC):
    # A laser on a wire (robots.lms2xx, robots.hokuyo) reports its link: False while it is
    # silent, sends garbage or is unplugged, with the reason in `link_error`. A simulated or
    # replayed laser is always up.
    link_up: bool = True
    link_error: str = ""

    @abstractmethod
    def read(self) -> LaserScan | None:
        """The newest scan, or None before the first one (and, on a wire, while the link is
        down: never a stale scan)."""


class PersonDetector(ABC):
    @abstractmethod
    def detect(self) -> list[Detection]:
        """Person detections of the newest frame (may include misses and false positives)."""

    def fault(self) -> str | None:
        """Why the detector cannot see now (a camera that stopped delivering frames), or None."""
        return None


class PanTiltHead(ABC):
    @abstractmethod
    def point(self, pan: float, tilt: float) -> None:
        """Move towards (pan, tilt) in rad, clamped to the head's range, at its own rate."""

    @abstractmethod
    def read(self) -> tuple[float, float]:
        """The current (pan, tilt) in rad."""

    def fault(self) -> str | None:
        """Why the head cannot be driven now (a silent or refusing link), or None. A head with
        a fault does not move; `read` then gives the last position it reported."""
        return None


class TouchScreen(ABC):
    """A touch screen: one prompt at a time (a question with answer buttons, optionally a text
    field), an information screen (text and an optional picture), and captions of speech."""

    source = "touch"    # how an answer from this screen is labelled: touch, sim (or voice)

    @abstractmethod
    def show(self, prompt_id: str, text: str, buttons: tuple[str, ...],
             typed: bool = False) -> None:
        """Show a question with answer buttons (and a text field when `typed`); a new call
        replaces the old prompt. A press comes back from `take_press` as (prompt_id, value)."""

    @abstractmethod
    def clear(self) -> None:
        """Show nothing (the idle screen)."""

    @abstractmethod
    def take_press(self) -> tuple[str, str] | None:
        """The (prompt_id, button or typed text) given since the last call, or None."""

    def take_press_from(self) -> tuple[str, str, str] | None:
        """Like `take_press`, with the press's source as a third item (a screen composed of
        several says which one was touched)."""
        press = self.take_press()
        return None if press is None else (press[0], press[1], self.source)

    def close(self) -> None:
        """Release what the screen holds (a server, a window); nothing by default."""

    def display(self, text: str, picture: str | None = None) -> None:
        """Show information without answers: a text and optionally a picture (a file path).
        Replaces any prompt. Screens that cannot show pictures show the text only."""

    def caption(self, text: str) -> None:
        """Show what the robot is saying as a caption (for people who cannot hear it)."""


class Speaker(ABC):
    @abstractmethod
    def say(self, text: str) -> None:
        """Speak `text` (text-to-speech on a robot; recorded by the simulation)."""

    @abstractmethod
    def busy(self) -> bool:
        """True while the last utterance is still being spoken."""

    def close(self) -> None:
        """Stop speaking and release the device; nothing by default."""


class AudioSource(ABC):
    """Sound to listen to: 16 kHz mono signed 16-bit samples, read in chunks."""

    rate = 16000

    @abstractmethod
    def read(self, frames: int) -> bytes | None:
        """Up to `frames` samples (2 bytes each); b"" when none are ready yet, None at the end."""

    def cue(self) -> None:
        """A question appeared. A microphone hears on regardless (nothing to do); a source of
        recorded answers plays its next one."""

    def close(self) -> None:
        """Release the device or file."""


class SpeechRecognizer(ABC):
    """Listens for one of a few expected answers (those on the screen), never for free speech."""

    @abstractmethod
    def listen(self, prompt_id: str, choices: tuple[str, ...]) -> None:
        """Listen for one of `choices` as the answer to `prompt_id` (replaces the old ones)."""

    @abstractmethod
    def stop(self) -> None:
        """Listen for nothing."""

    @abstractmethod
    def take_heard(self) -> tuple[str, str] | None:
        """An answer heard since the last call, as (prompt_id, choice), or None."""

    def close(self) -> None:
        """Stop listening and release the audio source."""
