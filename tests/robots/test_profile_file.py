"""Robot profiles from a file: any path is a profile, the bundled names stay the defaults, and
every mistake is named with file:line before anything is opened."""
from __future__ import annotations

import pytest

from robots.exceptions import ProfileError, UnknownRobotError
from robots.profile import PROFILE_DIR, is_profile_file, load_profile


def copy_of(name: str, tmp_path, *edits: tuple[str, str]):
    """The bundled profile `name` written to tmp_path with `edits` (old, new) applied."""
    text = (PROFILE_DIR / f"{name}.toml").read_text()
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    path = tmp_path / f"my_{name}.toml"
    path.write_text(text)
    return path


def line_of(path, fragment: str) -> int:
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if fragment in line)


@pytest.mark.parametrize("name", ["horos", "perses", "argos"])
def test_a_copy_of_each_bundled_profile_loads_from_its_path(name, tmp_path):
    path = copy_of(name, tmp_path, ('max_speed = ', 'max_speed = 0.2 # '))
    mine, bundled = load_profile(path), load_profile(name)
    assert mine.source == path and bundled.source == PROFILE_DIR / f"{name}.toml"
    assert mine.limits.max_speed == 0.2 and bundled.limits.max_speed > 0.2
    assert mine.base == bundled.base and mine.capabilities == bundled.capabilities
    assert load_profile(str(path)).limits.max_speed == 0.2


def test_names_and_files_are_told_apart():
    assert not is_profile_file("argos")
    for text in ("./argos.toml", "argos.toml", "robots/x", "/tmp/r.toml"):
        assert is_profile_file(text), text


@pytest.mark.parametrize("name, old, new, fragment, words", [
    ("argos", "right_mirrored = true", "right_mirored = true", "right_mirored",
     "[base] unknown canopen option 'right_mirored' (did you mean 'right_mirrored'?)"),
    ("argos", "wheel_radius = 0.0825", "wheel_radius = 5.0", "wheel_radius",
     "[base] wheel_radius = 5.0 outside the allowed range 0.01 .. 1.0"),
    ("argos", 'velocity_unit = "counts/s"', 'velocity_unit = "rpms"', 'velocity_unit = "rpms"',
     "[base] velocity_unit = 'rpms'; allowed: 'counts/s', 'rpm'"),
    ("argos", 'driver = "canopen"', 'driver = "canopn"', "canopn", "[base] driver = 'canopn'; known drivers:"),
    ("perses", "dist_conv = 101230.0", "dist_conv = 0.5", "dist_conv", "[base] dist_conv = 0.5; allowed 1 .. 1e7"),
    ("perses", "dist_conv", "dist_convv", "dist_convv", "[base] unknown rflex option 'dist_convv'"),
    ("horos", 'subclass = "p2dx"', 'sublass = "p2dx"', "sublass", "[base] unknown p2os option 'sublass'"),
    ("horos", "max_accel = ", "max_acel = ", "max_acel", "[limits] unknown key 'max_acel' (did you mean 'max_accel'?)"),
    ("horos", "max_speed = ", "max_speed = 9.0 #", "max_speed = 9.0",
     "[limits] max_speed = 9.0 is outside the allowed range 0.0 .. 3.0"),
    ("horos", 'shape = "rectangle"', 'shape = "oval"', "oval", "[geometry] shape = 'oval'; allowed"),
])
def test_mistakes_are_named_with_file_and_line(name, old, new, fragment, words, tmp_path):
    path = copy_of(name, tmp_path, (old, new))
    with pytest.raises(ProfileError) as err:
        load_profile(path)
    message = str(err.value)
    assert message.startswith(f"{path}:{line_of(path, fragment)}: "), message
    assert words in message, message


def test_invalid_toml_and_missing_files(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text('[robot]\nname = "x"\n[base\n')
    with pytest.raises(ProfileError, match=rf"^{path}:3: not valid TOML"):
        load_profile(path)
    with pytest.raises(ProfileError, match=r"nope.toml: no such robot profile file"):
        load_profile(tmp_path / "nope.toml")
    with pytest.raises(UnknownRobotError, match=r"unknown robot 'argoss'; known robots: argos, horos, perses"):
        load_profile("argoss")
