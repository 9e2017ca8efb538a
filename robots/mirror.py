"""Devices composed of several: one screen shown on two glasses, one voice through two speakers.

In simulation with `--gui` the tablet page stands beside the simulated screen: whatever the robot
shows goes to both, and a press on either counts, so the simulated people keep answering while a
person may answer by hand. The same holds for speech (simulated speaker and espeak-ng).
"""
from __future__ import annotations

from robots.devices import Speaker, TouchScreen


class MirroredTouchScreen(TouchScreen):
    def __init__(self, *screens: TouchScreen) -> None:
        if not screens:
            raise ValueError("a mirrored touch screen needs at least one screen")
        self.screens = screens
        self.source = screens[0].source

    def show(self, prompt_id: str, text: str, buttons: tuple[str, ...],
             typed: bool = False) -> None:
        for screen in self.screens:
            screen.show(prompt_id, text, buttons, typed)

    def display(self, text: str, picture: str | None = None) -> None:
        for screen in self.screens:
            screen.display(text, picture)

    def caption(self, text: str) -> None:
        for screen in self.screens:
            screen.caption(text)

    def clear(self) -> None:
        for screen in self.screens:
            screen.clear()

    def take_press_from(self) -> tuple[str, str, str] | None:
        """The first waiting press of any screen, labelled with that screen's source."""
        for screen in self.screens:
            press = screen.take_press_from()
            if press is not None:
                return press
        return None

    def take_press(self) -> tuple[str, str] | None:
        press = self.take_press_from()
        return None if press is None else (press[0], press[1])

    def close(self) -> None:
        for screen in self.screens:
            screen.close()


class MirroredSpeaker(Speaker):
    """Says everything through every speaker; busy while any of them is."""

    def __init__(self, *speakers: Speaker) -> None:
        if not speakers:
            raise ValueError("a mirrored speaker needs at least one speaker")
        self.speakers = speakers

    def say(self, text: str) -> None:
        for speaker in self.speakers:
            speaker.say(text)

    def busy(self) -> bool:
        return any(speaker.busy() for speaker in self.speakers)

    def close(self) -> None:
        for speaker in self.speakers:
            speaker.close()
