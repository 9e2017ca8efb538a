"""Devices' addresses from the command line (robots.addresses): checked with the profile's rules,
put over the profile's own, refused where the profile has no table for the device; and the
addresses that put the whole simulated robot on its wires."""
from __future__ import annotations

import pytest

from robots.addresses import check_address, wired_addresses, with_addresses
from robots.exceptions import ProfileError
from robots.profile import PROFILE_DIR, load_profile


def test_an_address_replaces_the_profile_s_and_keeps_the_rest_of_the_table():
    horos = load_profile("horos")
    wired = with_addresses(horos, {"laser": "lms200:/dev/ttyUSB3?baud=38400",
                                   "head": "visca:socket://127.0.0.1:5000", "camera": None})
    assert wired.laser.device == "lms200:/dev/ttyUSB3?baud=38400"
    assert wired.head.device == "visca:socket://127.0.0.1:5000"
    assert (wired.laser.fov, wired.laser.beams, wired.head.pan_max) == \
        (horos.laser.fov, horos.laser.beams, horos.head.pan_max)
    assert wired.camera == horos.camera


@pytest.mark.parametrize("device, text, simulated, words", [
    ("laser", "sick:/dev/ttyUSB0", False, "allowed: lms200, lms291, urg, ust"),
    ("laser", "lms200:", False, "no address after 'lms200:'"),
    ("laser", "lms200:/dev/ttyUSB0?speed=9600", False, "option 'speed' is not one of"),
    ("laser", "lms200:/dev/ttyUSB0?baud=fast", False, "must be a whole number"),
    ("laser", "lms200:/dev/ttyUSB0", True, "'lms200:sim'"),
    ("head", "pelco:/dev/ttyUSB1", False, "DRIVER one of visca"),
    ("head", "visca:", False, "no address after 'visca:'"),
    ("head", "", False, "empty address"),
    ("sonar", "x:y", False, "allowed: laser, head, camera"),
])
def test_a_mistaken_address_says_what_is_allowed(device, text, simulated, words):
    with pytest.raises(ProfileError) as refused:
        check_address(device, text, simulated=simulated)
    assert words in str(refused.value)


def test_a_device_the_profile_has_no_table_for_is_refused():
    with pytest.raises(ProfileError) as refused:
        with_addresses(load_profile("perses"), {"head": "visca:/dev/ttyUSB1"})
    assert "robot 'perses' has no [head]" in str(refused.value)


def test_the_whole_robot_on_its_wires_names_each_emulator(tmp_path):
    assert wired_addresses(load_profile("horos")) == {"laser": "lms200:sim", "head": "visca:sim"}
    assert wired_addresses(load_profile("perses")) == {"laser": "lms200:sim"}
    own = tmp_path / "hokuyo_horos.toml"     # a profile naming its own laser: that kind, emulated
    own.write_text((PROFILE_DIR / "horos.toml").read_text().replace(
        "[laser]\n", '[laser]\ndevice = "urg:/dev/ttyACM0?cluster=2"\n', 1))
    assert wired_addresses(load_profile(own))["laser"] == "urg:sim?cluster=2"
