"""A registered plugin's section is validated by its own `Params`, with the same error quality."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from pydantic import Field

from btnav.core.errors import BtnavWarning, ParamsError
from btnav.params import ParamsModel, Why, ignored, load_params
from btnav.plugins import register, unregister

PLANNER = "btnav_test::StraightLine"


@pytest.fixture
def planner() -> Iterator[type]:
    @register("planner", PLANNER)
    class StraightLine:
        class Params(ParamsModel):
            step: float = Field(0.05, gt=0.0)
            visualize: bool = ignored(False, Why.VIZ)

    yield StraightLine
    unregister("planner", PLANNER)


@pytest.fixture
def bare_planner() -> Iterator[type]:
    @register("planner", PLANNER)
    class NoParamsPlanner:
        pass

    yield NoParamsPlanner
    unregister("planner", PLANNER)


def planner_file(tmp_path: Path, body: str = "") -> Path:
    path = tmp_path / "p.yaml"
    path.write_text(
        "planner_server:\n"
        "  ros__parameters:\n"
        "    planner_plugins: [Straight]\n"
        "    Straight:\n"
        f"      plugin: {PLANNER}\n" + body
    )
    return path


def test_params_are_validated_and_ignored_keys_listed(tmp_path: Path, planner: type) -> None:
    params = load_params(planner_file(tmp_path, "      step: 0.1\n      visualize: true\n"))
    section = params.server("planner_server").plugins["Straight"]
    assert (section.cls, section.params.step) == (planner, 0.1)
    [entry] = params.ignored_under("planner_server.Straight")
    assert (entry.key, entry.line, entry.reason) == (
        "planner_server.Straight.visualize",
        7,
        Why.VIZ,
    )


def test_out_of_range_plugin_param(tmp_path: Path, planner: type) -> None:
    with pytest.raises(ParamsError) as info:
        load_params(planner_file(tmp_path, "      step: -1\n"))
    assert (info.value.line, info.value.key) == (6, "planner_server.Straight.step")


def test_the_registry_lists_registered_names_for_a_typo(tmp_path: Path, planner: type) -> None:
    path = planner_file(tmp_path)
    path.write_text(path.read_text().replace(PLANNER, "btnav_test::StraightLne"))
    with pytest.raises(ParamsError) as info:
        load_params(path)
    assert info.value.suggestion == "btnav_test/StraightLine"
    assert info.value.key == "planner_server.Straight.plugin"


def test_a_plugin_without_params_reads_no_keys(tmp_path: Path, bare_planner: type) -> None:
    section = load_params(planner_file(tmp_path)).server("planner_server").plugins["Straight"]
    assert section.cls is bare_planner
    path = planner_file(tmp_path, "      step: 0.1\n")
    with pytest.warns(BtnavWarning) as caught:  # Nav2 would skip it too: not a near miss
        params = load_params(path)
    assert [(w.message.line, w.message.key) for w in caught] == [
        (6, "planner_server.Straight.step")
    ]
    assert "(not a parameter StraightLine reads); Nav2 ignores it too" in str(caught[0].message)
    assert params.server("planner_server").plugins["Straight"].cls is bare_planner
