"""Fixtures of the viz tests."""

from __future__ import annotations

import pytest

from btnav.plugins import register, unregister
from btnav.viz.run_gif import RunGif


@pytest.fixture
def gif_probe():
    """The `gif` output under another name, keeping each instance (its recorder) to look at."""
    made: list[RunGif] = []

    @register("output", "gif_probe")
    class Probe(RunGif):
        def __init__(self) -> None:
            super().__init__()
            made.append(self)

    yield made
    unregister("output", "gif_probe")
