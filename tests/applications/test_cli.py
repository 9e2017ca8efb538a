"""The command line: listings, trees, and one-line errors (exit 2, no traceback) for unknown names."""
import subprocess
import sys

import pytest

from applications.cli import main


def interbot(*args):
    return subprocess.run([sys.executable, "-m", "applications.cli", *args],
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("args, names", [
    (("run", "survey", "--robot", "robby", "--fast"), ["horos", "perses"]),
    (("run", "survy", "--fast"), ["survey"]),
    (("run", "survey", "--scenario", "crowd", "--fast"), ["complete", "nobody"]),
    (("tree", "FaceUsr"), ["FaceUser", "Survey"]),
])
def test_unknown_names_get_one_line_naming_what_exists(args, names, tmp_path):
    result = interbot(*args, *(["--data", str(tmp_path)] if args[0] == "run" else []))
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("interbot: error:")
    for name in names:
        assert name in lines[0]


def test_listings(capsys):
    assert main(["behaviors"]) == 0
    out = capsys.readouterr().out
    assert "FaceUser" in out and "pan_tilt" in out
    assert main(["robots"]) == 0
    out = capsys.readouterr().out
    lines = {line.split()[0]: line for line in out.splitlines()}
    assert {"horos", "perses", "argos"} <= set(lines)
    assert "pan_tilt" in lines["horos"] and "pan_tilt" not in lines["argos"]


def test_tree_renders_the_realization_of_the_robot(capsys):
    assert main(["tree", "Survey", "--robot", "perses"]) == 0
    out = capsys.readouterr().out
    assert "TurnToUser" in out and "AskQuestions" in out
    assert main(["tree", "FaceUser", "--format", "dot"]) == 0
    assert "digraph" in capsys.readouterr().out
