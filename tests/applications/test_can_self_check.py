"""A CAN robot whose profile contradicts how its motors are mounted is refused before it drives,
with one line (issue 24 point 1): the start-up self-check's turns, seen by the laser, disagree
with the profile's `right_mirrored`. The emulated drives are mounted as ARGOS's really are."""
from __future__ import annotations

from applications.cli import main
from robots.canopen.emulator import CanOpenEmulator
from robots.profile import load_profile


def mounted_as_argos(monkeypatch):
    original = CanOpenEmulator.__init__

    def init(self, *args, **kw):
        original(self, *args, **kw)
        self.mirrored[2] = True                 # the right motor is mounted mirrored, whatever
    monkeypatch.setattr(CanOpenEmulator, "__init__", init)


def test_a_profile_with_the_wrong_mirroring_is_refused_in_one_line(monkeypatch, tmp_path, capsys):
    mounted_as_argos(monkeypatch)
    text = load_profile("argos").source.read_text()
    assert "right_mirrored = true" in text
    robot = tmp_path / "my_argos.toml"
    robot.write_text(text.replace("right_mirrored = true", "right_mirrored = false"))
    code = main(["run", "survey", "--robot", str(robot), "--fast", "--duration", "2",
                 "--data", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert "node 2 (right wheel)" in err[0] and "set right_mirrored = true" in err[0], err
    assert "refused before driving" in err[0]


def test_the_right_mirroring_passes(monkeypatch, tmp_path, capsys):
    mounted_as_argos(monkeypatch)
    code = main(["run", "survey", "--robot", "argos", "--fast", "--duration", "2", "--data", str(tmp_path)])
    assert code == 0, capsys.readouterr().err
