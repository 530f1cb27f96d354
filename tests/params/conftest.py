"""Fixtures for params tests: an editable copy of Nav2's file and temporary plugins."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from pydantic import Field

from btnav.params import ParamsModel
from btnav.plugins import register, unregister

from .tutorial import DOCUMENTED_CRITICS, with_tutorial_sections

#: A made-up plugin type (not a Nav2 name), so nothing real is replaced while a test runs.
TEST_INFLATION = "btnav_test::InflationLayer"


@pytest.fixture
def nav2_copy(tmp_path: Path, nav2_params_file: Path) -> Callable[..., tuple[Path, int]]:
    """`nav2_copy(old, new)`: Nav2's file with the one line holding `old` edited.

    Returns the new file and the (1-based) line of the edit, so a test can assert
    the error names exactly that line.
    """

    def make(old: str = "", new: str = "", *, count: int = 1, name: str = "params.yaml"):
        lines = nav2_params_file.read_text().splitlines(keepends=True)
        hits = [i for i, line in enumerate(lines) if old and old in line]
        if old:
            assert len(hits) >= count, f"{old!r} found {len(hits)} times"
            for i in hits[:count]:
                lines[i] = lines[i].replace(old, new, 1)
        out = tmp_path / name
        out.write_text("".join(lines))
        return out, (hits[0] + 1 if hits else 0)

    return make


@pytest.fixture
def tutorial_params(tmp_path: Path, nav2_params_file: Path) -> Path:
    """Nav2's params file with the Jazzy tutorial's three sections pasted in (issue 34)."""
    return with_tutorial_sections(
        nav2_params_file, tmp_path / "tutorial_params.yaml", critics=DOCUMENTED_CRITICS
    )


@pytest.fixture
def inflation_plugin() -> Iterator[type]:
    """A costmap layer registered as TEST_INFLATION while the test runs."""

    @register("costmap_layer", TEST_INFLATION)
    class TestInflation:
        class Params(ParamsModel):
            inflation_radius: float = Field(0.55, gt=0.0)
            cost_scaling_factor: float = Field(10.0, gt=0.0)
            enabled: bool = True

    yield TestInflation
    unregister("costmap_layer", TEST_INFLATION)


@pytest.fixture
def with_test_inflation(
    nav2_copy: Callable[..., tuple[Path, int]], inflation_plugin: type
) -> Callable[..., tuple[Path, int]]:
    """Like `nav2_copy`, with every InflationLayer section pointing at the temporary plugin."""

    def make(old: str = "", new: str = "", *, count: int = 1) -> tuple[Path, int]:
        base, _ = nav2_copy(
            "nav2_costmap_2d::InflationLayer", TEST_INFLATION, count=2, name="base.yaml"
        )
        lines = base.read_text().splitlines(keepends=True)
        hits = [i for i, line in enumerate(lines) if old and old in line]
        for i in hits[:count]:
            lines[i] = lines[i].replace(old, new, 1)
        out = base.with_name("params.yaml")
        out.write_text("".join(lines))
        return out, (hits[0] + 1 if hits else 0)

    return make
