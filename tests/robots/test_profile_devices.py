"""The profile's device tables: [head] model and device, [camera]; a wrong value names the
file, the table, the key and what is allowed."""
from __future__ import annotations

import math

import pytest

from robots.exceptions import ProfileError
from robots.profile import PROFILE_DIR, load_profile


def horos_with(tmp_path, table: str, lines: str):
    text = (PROFILE_DIR / "horos.toml").read_text().replace('model = "evi-d31"\n', "")
    if f"[{table}]\n" in text:
        text = text.replace(f"[{table}]\n", f"[{table}]\n{lines}\n", 1)
    else:
        text += f"\n[{table}]\n{lines}\n"
    path = tmp_path / "robot.toml"
    path.write_text(text)
    return path


def test_the_bundled_horos_names_its_head_model_and_no_devices():
    horos = load_profile("horos")
    assert horos.head.model == "evi-d31" and horos.head.device == ""
    assert horos.camera is None


def test_head_device_and_model(tmp_path):
    head = load_profile(horos_with(tmp_path, "head", 'device = "visca:/dev/ttyUSB1"')).head
    assert head.device == "visca:/dev/ttyUSB1"


def test_a_camera_table(tmp_path):
    camera = load_profile(horos_with(tmp_path, "camera", 'device = "/dev/video0"\n'
                                     'heading_deg = 10\non_head = true\ndetect = ["face"]\n'
                                     'bearing_sd_deg = 3')).camera
    assert camera.device == "/dev/video0" and camera.on_head and camera.detect == ("face",)
    assert camera.heading == pytest.approx(math.radians(10))
    assert camera.bearing_sd == pytest.approx(math.radians(3))
    assert (camera.hfov_deg, camera.width, camera.height) == (48.8, 640, 480)   # defaults


@pytest.mark.parametrize("table, lines, says", [
    ("head", 'model = "evi-d100"', "[head] model = 'evi-d100'; allowed: 'evi-d31', 'evi-d70'"),
    ("head", "device = 3", "[head] device = 3 must be a string"),
    ("camera", "fov = 60", "[camera] unknown key(s) fov; known:"),
    ("camera", 'detect = ["hands"]', "[camera] detect = ['hands']; allowed a non-empty list"),
    ("camera", "hfov_deg = 200", "[camera] hfov_deg = 200 is outside the allowed range 1.0 .. 179.0"),
])
def test_a_wrong_device_value_names_file_table_and_range(tmp_path, table, lines, says):
    with pytest.raises(ProfileError) as info:
        load_profile(horos_with(tmp_path, table, lines))
    assert str(info.value).startswith(str(tmp_path / "robot.toml"))
    assert says in str(info.value)
