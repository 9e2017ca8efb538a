"""The interaction options of `open_hardware`: the tablet page and espeak-ng join the simulated
screen and speaker; capabilities follow what is actually opened."""
from __future__ import annotations

from robots.audio.espeak import EspeakSpeaker
from robots.hardware import open_hardware
from robots.mirror import MirroredSpeaker, MirroredTouchScreen
from robots.sim.devices import SimSpeaker, SimTouchScreen
from robots.tablet import WebTouchScreen


def test_simulation_without_options_opens_no_server_and_no_real_voice():
    hardware = open_hardware("horos", fast=True)
    try:
        assert isinstance(hardware.screen, SimTouchScreen)
        assert isinstance(hardware.speaker, SimSpeaker)
        assert hardware.tablet_url is None and hardware.recognizer is None
        assert "speech_in" not in hardware.capabilities
    finally:
        hardware.close()


def test_simulation_with_the_page_and_wav_speech_composes_both(tmp_path):
    hardware = open_hardware("horos", fast=True, gui="127.0.0.1:0", speech_wav=tmp_path,
                             language="de")
    try:
        screen, speaker = hardware.screen, hardware.speaker
        assert isinstance(screen, MirroredTouchScreen) and isinstance(speaker, MirroredSpeaker)
        assert [type(s) for s in screen.screens] == [SimTouchScreen, WebTouchScreen]
        assert [type(s) for s in speaker.speakers] == [SimSpeaker, EspeakSpeaker]
        assert speaker.speakers[1].voice == "de"
        assert hardware.tablet_url.startswith("http://127.0.0.1:")
        assert {"touch_screen", "speech_out"} <= hardware.capabilities
        page = screen.screens[1]
    finally:
        hardware.close()
    assert not page.server._thread.is_alive()      # closing the robot stops the page


def test_listening_without_a_microphone_is_a_note_not_a_crash(monkeypatch):
    import robots.audio.source as source

    def no_device(*args, **kwargs):
        raise source.RobotError("no microphone: arecord failed: no capture device")
    monkeypatch.setattr(source, "MicrophoneSource", no_device)
    hardware = open_hardware("horos", fast=True, listen=True)
    try:
        assert hardware.recognizer is None and "speech_in" not in hardware.capabilities
        assert any("no microphone" in note for note in hardware.notes)
    finally:
        hardware.close()


def test_a_page_open_to_the_network_is_one_warning_at_start_and_tablets_are_paired(
        tmp_path, monkeypatch):
    monkeypatch.setenv("INTERBOT_TABLET_SECRET", str(tmp_path / "tablet-secret"))
    hardware = open_hardware("horos", fast=True, gui="0.0.0.0:0")
    try:
        warnings = [note for note in hardware.notes if "tablet page" in note]
        assert len(warnings) == 1 and "\n" not in warnings[0]
        assert warnings[0].startswith("warning: the tablet page listens on 0.0.0.0:")
        assert hardware.screen.screens[1].guard.tablet_pass is not None
        assert (tmp_path / "tablet-secret").stat().st_size == 32
    finally:
        hardware.close()
    local = open_hardware("horos", fast=True, gui="127.0.0.1:0")
    try:
        assert not any("tablet page" in note for note in local.notes)
    finally:
        local.close()
