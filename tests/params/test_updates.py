"""Params changed after loading (Nav2's dynamic parameters, `--set`) are validated like a file."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.core.errors import ParamsError
from btnav.params import apply_overrides, load_params, parse_set_option, validate_update


@pytest.fixture
def params(nav2_params_file: Path):
    return load_params(nav2_params_file)


def test_server_key_update_is_kept(params) -> None:
    server = validate_update(params, "local_costmap", {"update_frequency": 2.0})
    assert server.model.update_frequency == 2.0
    assert params.server("local_costmap").model.update_frequency == 2.0
    # The rest of the server is as the file had it.
    assert server.model.rolling_window is True
    assert list(server.plugins) == ["voxel_layer", "inflation_layer", "keepout_filter"]


def test_a_wrong_update_is_refused_and_nothing_changes(params) -> None:
    with pytest.raises(ParamsError) as info:
        validate_update(params, "local_costmap", {"width": 10, "update_frequency": -1.0})
    err = info.value
    assert err.key == "local_costmap.local_costmap.update_frequency"
    assert err.file is None and err.line is None
    assert "set_parameters" in err.message
    model = params.server("local_costmap").model
    assert (model.update_frequency, model.width) == (5.0, 3)


def test_misspelt_update_suggests(params) -> None:
    with pytest.raises(ParamsError) as info:
        validate_update(params, "controller_server", {"controller_frequncy": 10.0})
    assert info.value.suggestion == "controller_frequency"
    assert info.value.key == "controller_server.controller_frequncy"


def test_plugin_section_update_uses_the_plugins_params(with_test_inflation) -> None:
    path, _ = with_test_inflation()
    params = load_params(path)
    server = validate_update(params, "local_costmap", {"inflation_layer.inflation_radius": 0.5})
    assert server.plugins["inflation_layer"].params.inflation_radius == 0.5
    with pytest.raises(ParamsError) as info:
        validate_update(params, "local_costmap", {"inflation_layer.inflation_radus": 0.5})
    assert info.value.suggestion == "inflation_radius"
    assert params.server("local_costmap").plugins["inflation_layer"].params.inflation_radius == 0.5


def test_plugin_lists_cannot_change_while_running(params) -> None:
    with pytest.raises(ParamsError, match="cannot change while running"):
        validate_update(params, "controller_server", {"controller_plugins": ["A"]})
    with pytest.raises(ParamsError, match="cannot change while running"):
        validate_update(params, "controller_server", {"FollowPath.plugin": "x::Y"})


def test_unknown_server_in_update(params) -> None:
    with pytest.raises(ParamsError) as info:
        validate_update(params, "controler_server", {"controller_frequency": 1.0})
    assert info.value.suggestion == "controller_server"


def test_overrides_make_a_new_params_file(params) -> None:
    new = apply_overrides(
        params,
        {
            "local_costmap.local_costmap.inflation_layer.inflation_radius": 0.5,
            "controller_server.controller_frequency": 10,
            "global_costmap.resolution": 0.1,  # the repeated costmap name is optional
            "amcl.ros__parameters.max_particles": 3000,  # so is ros__parameters
        },
    )
    assert new.server("controller_server").model.controller_frequency == 10.0
    assert new.server("global_costmap").model.resolution == 0.1
    assert new.server("amcl").model.max_particles == 3000
    layer = new.server("local_costmap").doc["inflation_layer"]
    assert layer["inflation_radius"] == 0.5
    # The loaded file is untouched.
    assert params.server("controller_server").model.controller_frequency == 20.0
    assert params.raw["controller_server"]["ros__parameters"]["controller_frequency"] == 20.0


def test_override_of_a_server_the_file_lacks(tmp_path: Path) -> None:
    path = tmp_path / "p.yaml"
    path.write_text("amcl:\n  ros__parameters: {}\n")
    new = apply_overrides(load_params(path), {"local_costmap.local_costmap.width": 7})
    server = new.server("local_costmap")
    assert server.in_file and server.key == "local_costmap.local_costmap"
    assert server.model.width == 7


def test_bad_override_names_set_not_the_file(params) -> None:
    with pytest.raises(ParamsError) as info:
        apply_overrides(params, {"controller_server.controller_frequency": -5})
    err = info.value
    assert (err.file, err.line, err.key) == (None, None, "controller_server.controller_frequency")
    assert "--set" in err.message
    with pytest.raises(ParamsError) as info:
        apply_overrides(params, {"controler_server.controller_frequency": 5})
    assert info.value.suggestion == "controller_server"
    with pytest.raises(ParamsError, match="names a server"):
        apply_overrides(params, {"amcl": 5})
    with pytest.raises(ParamsError, match="not a section"):
        apply_overrides(params, {"amcl.alpha1.x": 5})


@pytest.mark.parametrize(
    "text, expected",
    [
        ("a.b=0.5", ("a.b", 0.5)),
        ("a.b = true", ("a.b", True)),
        ("a.b=[1, 2]", ("a.b", [1, 2])),
        ("a.b=base_link", ("a.b", "base_link")),
    ],
)
def test_parse_set_option(text: str, expected: tuple) -> None:
    assert parse_set_option(text) == expected


def test_parse_set_option_errors() -> None:
    with pytest.raises(ParamsError, match="KEY=VALUE"):
        parse_set_option("no_equals")
    with pytest.raises(ParamsError, match="cannot read the value"):
        parse_set_option("a=[1, 2")
