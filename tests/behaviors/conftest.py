"""Fixtures for behaviour tests."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from .stack import OFFICE, Stack, make_stack, write_world


@pytest.fixture
def office(tmp_path: Path) -> Any:
    """`office(pose)`: the small office, robot starting at `pose`, exact odometry, stack built."""

    def make(pose: tuple[float, float, float] = (2.0, 1.5, 0.0), params: Any = None) -> Stack:
        text = OFFICE.read_text().replace("pose: [1.0, 1.0, 0.0]", f"pose: {list(pose)}")
        # Noise-free odometry: behaviours measure their motion in odom, as Nav2's do, so
        # odometry drift would show as an error of the behaviour.
        text = text.replace("noise: [0.002, 0.0005, 0.0001, 0.0001]", "noise: [0.0, 0.0, 0.0, 0.0]")
        return make_stack(write_world(tmp_path, text), params)

    return make
