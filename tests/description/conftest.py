"""The machine's own Gazebo model paths stay out of the description tests."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def no_gazebo_env(monkeypatch: pytest.MonkeyPatch) -> None:
    for var in ("GZ_SIM_RESOURCE_PATH", "GAZEBO_MODEL_PATH"):
        monkeypatch.delenv(var, raising=False)
