"""The four-layer rule, checked by import-linter: on the real tree, and on a tree that breaks it."""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def lint_imports(cwd: Path, pythonpath: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(pythonpath))
    return subprocess.run([sys.executable, "-c", "from importlinter.cli import lint_imports_command;"
                           "lint_imports_command()"],
                          cwd=cwd, env=env, capture_output=True, text=True, timeout=120)


def test_contracts_hold_on_the_real_tree():
    result = lint_imports(REPO, REPO)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 broken" in result.stdout


def _package(root: Path, name: str, source: str = "") -> None:
    (root / name).mkdir()
    (root / name / "__init__.py").write_text(textwrap.dedent(source))


def test_an_upward_or_floor_skipping_import_breaks_the_contract(tmp_path):
    """The same contracts on a toy tree where applications reaches robots directly."""
    (tmp_path / "setup.cfg").write_text((REPO / "setup.cfg").read_text())
    _package(tmp_path, "robots")
    _package(tmp_path, "skills", "import robots\n")
    _package(tmp_path, "behaviors", "import skills\n")
    _package(tmp_path, "applications", "import behaviors\nimport robots\n")
    result = lint_imports(tmp_path, tmp_path)
    assert result.returncode != 0
    assert "applications (L3) does not reach skills (L1) or robots (L0) BROKEN" in result.stdout


def test_an_upward_import_breaks_the_layers_contract(tmp_path):
    (tmp_path / "setup.cfg").write_text((REPO / "setup.cfg").read_text())
    _package(tmp_path, "robots", "import skills\n")
    _package(tmp_path, "skills")
    _package(tmp_path, "behaviors", "import skills\n")
    _package(tmp_path, "applications", "import behaviors\n")
    result = lint_imports(tmp_path, tmp_path)
    assert result.returncode != 0
    assert "each imports only its immediate lower neighbour BROKEN" in result.stdout
