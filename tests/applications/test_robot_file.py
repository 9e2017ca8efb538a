"""`--robot ./my_robot.toml` everywhere a robot name is: run, check, tree, percepts, emulate;
a mistake in the file is one line with file:line and exit 2, before anything is opened."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from robots.profile import PROFILE_DIR

REPO = Path(__file__).resolve().parents[2]


def interbot(*args, cwd):
    return subprocess.run([sys.executable, "-m", "applications.cli", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=120,
                          env={"PYTHONPATH": str(REPO), "PATH": "/usr/bin:/bin"})


@pytest.fixture
def my_robot(tmp_path):
    """ARGOS as a user's file, relative to the working directory, slower."""
    text = (PROFILE_DIR / "argos.toml").read_text().replace("max_speed = 0.6", "max_speed = 0.4")
    (tmp_path / "my_robot.toml").write_text(text)
    return tmp_path


def test_run_and_check_take_a_profile_file(my_robot):
    result = interbot("run", "survey", "--robot", "./my_robot.toml", "--fast", "--quiet",
                      "--duration", "5", "--data", str(my_robot), cwd=my_robot)
    assert result.returncode == 0, result.stderr
    assert "running 'survey' on" in result.stdout and "my_robot.toml" in result.stdout
    result = interbot("check", "survey", "--robot", "./my_robot.toml", cwd=my_robot)
    assert result.returncode == 0 and "0 errors" in result.stdout, result.stdout + result.stderr
    for args in (("tree", "FaceUser", "--robot", "my_robot.toml"), ("percepts", "--robot", "./my_robot.toml")):
        result = interbot(*args, cwd=my_robot)
        assert result.returncode == 0, (args, result.stderr)


@pytest.mark.parametrize("command", [
    ("run", "survey", "--fast", "--duration", "5"),
    ("check", "survey"),
    ("emulate", "can"),
])
def test_a_mistake_in_the_file_is_one_line_with_file_and_line(my_robot, command):
    path = my_robot / "my_robot.toml"
    path.write_text(path.read_text().replace("track_width = 0.42", "track_width = 42"))
    line = next(n for n, text in enumerate(path.read_text().splitlines(), 1) if "track_width" in text)
    result = interbot(*command, "--robot", "./my_robot.toml", cwd=my_robot)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    assert f"my_robot.toml:{line}: [base] track_width = 42.0 outside the allowed range" in lines[0]
