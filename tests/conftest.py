"""Shared test fixtures: where Nav2's own files live."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED_NAV2 = REPO.parent / "shared" / "nav2"

pytest_plugins = ["pytester"]  # tests/testing runs a user's project with it


@pytest.fixture(scope="session")
def nav2_dir() -> Path:
    if not SHARED_NAV2.is_dir():
        pytest.fail(f"Nav2's corpus is missing: expected {SHARED_NAV2} beside the repo")
    return SHARED_NAV2


@pytest.fixture(scope="session")
def nav2_params_file(nav2_dir: Path) -> Path:
    return nav2_dir / "params" / "nav2_params.yaml"
