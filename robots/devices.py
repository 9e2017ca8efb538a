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
    """One person candidate in the robot frame, with its position covariance (m^2)."""
    t: float
    x: float
    y: float
    cov: tuple[tuple[float, float], tuple[float, float]]
    source: str = "camera"


class Laser(ABC):
    @abstractmethod
    def read(self) -> LaserScan | None:
        """The newest scan, or None before the first one."""


class PersonDetector(ABC):
    @abstractmethod
    def detect(self) -> list[Detection]:
        """Person detections of the newest frame (may include misses and false positives)."""


class PanTiltHead(ABC):
    @abstractmethod
    def point(self, pan: float, tilt: float) -> None:
        """Move towards (pan, tilt) in rad, clamped to the head's range, at its own rate."""

    @abstractmethod
    def read(self) -> tuple[float, float]:
        """The current (pan, tilt) in rad."""


class TouchScreen(ABC):
    @abstractmethod
    def show(self, prompt_id: str, text: str, buttons: tuple[str, ...]) -> None:
        """Show a text with answer buttons; a new call replaces the old prompt."""

    @abstractmethod
    def clear(self) -> None:
        """Show nothing."""

    @abstractmethod
    def take_press(self) -> tuple[str, str] | None:
        """The (prompt_id, button) pressed since the last call, or None."""


class Speaker(ABC):
    @abstractmethod
    def say(self, text: str) -> None:
        """Speak `text` (text-to-speech on a robot; recorded by the simulation)."""

    @abstractmethod
    def busy(self) -> bool:
        """True while the last utterance is still being spoken."""
