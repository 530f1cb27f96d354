"""The code stays as ruff's config in pyproject.toml asks (a failing lint fails CI)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def test_ruff_check_passes():
    ruff = shutil.which("ruff")
    if ruff is None:
        pytest.skip("ruff is not installed (it comes with the test extra)")
    out = subprocess.run(
        [ruff, "check", "src", "tests", "bench"], cwd=REPO, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stdout + out.stderr


def test_every_module_imports():
    """A module that only a rarely used command imports must still import."""
    out = subprocess.run(
        [
            sys.executable,
            "-c",
            "import btnav, pkgutil, importlib; "
            "[importlib.import_module(m.name) for m in pkgutil.walk_packages(btnav.__path__, 'btnav.')]",
        ],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr
