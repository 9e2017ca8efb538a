""".ci/run on a machine without the Debian packages the tests need (Graphviz, espeak-ng,
Chromium and its driver): apt-get through sudo when not root, and a clear message naming the
packages when neither root nor sudo can install them. Every other command the
script runs is a stub that records its arguments, so nothing is installed and no test runs."""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / ".ci" / "run"
RECORDER = '#!/bin/sh\necho "${0##*/} $*" >> "$CALLS"\n{body}\n'


def fake_machine(tmp_path: Path, uid: int, commands: dict[str, str]) -> dict[str, str]:
    """A PATH holding only stubs (and dirname), as on a machine where `dot`, `espeak-ng`,
    `chromium` and `chromedriver` are missing (unless `commands` stubs them)."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    os.symlink(shutil.which("dirname"), bin_dir / "dirname")
    stubs = {"python3": "exit 0", "lint-imports": "exit 0", "id": f"echo {uid}", **commands}
    for name, body in stubs.items():
        path = bin_dir / name
        path.write_text(RECORDER.replace("{body}", body))
        path.chmod(0o755)
    return {"PATH": str(bin_dir), "CALLS": str(tmp_path / "calls")}


def run_ci(tmp_path, env):
    result = subprocess.run([shutil.which("bash"), str(SCRIPT)], env=env, capture_output=True,
                            text=True, timeout=60)
    calls = (tmp_path / "calls").read_text().splitlines() if (tmp_path / "calls").exists() else []
    return result, calls


EVERY = "graphviz espeak-ng chromium chromium-driver"


def test_not_root_installs_the_packages_through_sudo(tmp_path):
    env = fake_machine(tmp_path, 1000, {"sudo": '"$@"', "apt-get": "exit 0"})
    result, calls = run_ci(tmp_path, env)
    assert "sudo apt-get update -qq" in calls
    assert f"sudo apt-get install -y -qq {EVERY}" in calls
    assert result.returncode == 0, result.stderr


def test_only_the_missing_packages_are_installed(tmp_path):
    env = fake_machine(tmp_path, 0, {"apt-get": "exit 0", "dot": "exit 0",
                                     "chromedriver": "exit 0"})
    result, calls = run_ci(tmp_path, env)
    assert "apt-get install -y -qq espeak-ng chromium" in calls
    assert result.returncode == 0, result.stderr


def test_nothing_is_installed_when_everything_is_there(tmp_path):
    env = fake_machine(tmp_path, 1000, {name: "exit 0" for name in
                                        ("dot", "espeak-ng", "chromium", "chromedriver")})
    result, calls = run_ci(tmp_path, env)
    assert not any("apt-get" in c for c in calls)
    assert result.returncode == 0, result.stderr


def test_root_uses_apt_get_directly(tmp_path):
    env = fake_machine(tmp_path, 0, {"apt-get": "exit 0"})
    result, calls = run_ci(tmp_path, env)
    assert f"apt-get install -y -qq {EVERY}" in calls
    assert not any(c.startswith("sudo") for c in calls)
    assert result.returncode == 0, result.stderr


@pytest.mark.parametrize("commands", [{"apt-get": "exit 0"},                   # no sudo
                                      {"sudo": "exit 1", "apt-get": "exit 0"}])  # sudo refuses
def test_without_root_or_sudo_it_says_what_to_install(tmp_path, commands):
    env = fake_machine(tmp_path, 1000, commands)
    result, calls = run_ci(tmp_path, env)
    assert result.returncode == 1
    assert EVERY in result.stderr and "'dot'" in result.stderr
    assert not any(c.startswith("lint-imports") for c in calls)


def test_foxglove_s_reader_is_installed_from_the_lock_file_where_npm_is(tmp_path):
    present = {name: "exit 0" for name in ("dot", "espeak-ng", "chromium", "chromedriver")}
    result, calls = run_ci(tmp_path, fake_machine(tmp_path, 0, {**present, "npm": "exit 0"}))
    assert result.returncode == 0, result.stderr
    assert any(c.startswith("npm ci --prefix tests/js") for c in calls), calls
    (tmp_path / "calls").unlink()
    other = tmp_path / "without"
    other.mkdir()
    result, calls = run_ci(other, fake_machine(other, 0, present))
    assert result.returncode == 0, result.stderr
    assert not any(c.startswith("npm") for c in calls)
