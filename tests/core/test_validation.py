"""Schema errors point into the file: line, key path and the closest spelling."""

from __future__ import annotations

import pytest
from pydantic import Field

from btnav.core.errors import ConfigError
from btnav.core.validation import StrictModel, validate
from btnav.core.yaml_io import load_yaml_text


class Inflation(StrictModel):
    inflation_radius: float = Field(0.55, gt=0)
    cost_scaling_factor: float = Field(10.0, ge=0)


class Costmap(StrictModel):
    update_frequency: float = Field(5.0, gt=0)
    inflation_layer: Inflation = Inflation()
    layers: list[Inflation] = []


def check(text: str) -> ConfigError:
    with pytest.raises(ConfigError) as info:
        validate(Costmap, load_yaml_text(text, "costmap.yaml"))
    return info.value


def test_misspelt_nested_key_names_file_line_path_and_spelling():
    err = check("update_frequency: 1.0\ninflation_layer:\n  inflaton_radius: 1.0\n")
    assert (err.file, err.line, err.key) == ("costmap.yaml", 3, "inflation_layer.inflaton_radius")
    assert err.suggestion == "inflation_radius"
    assert str(err).startswith("costmap.yaml:3: inflation_layer.inflaton_radius: unknown key")


def test_out_of_range_value_names_its_line():
    err = check("update_frequency: 1.0\ninflation_layer:\n  inflation_radius: -2\n")
    assert err.line == 3 and "greater than 0" in err.message and "-2" in err.message


def test_errors_inside_lists_name_the_item():
    err = check("layers:\n  - {inflation_radius: 1}\n  - {cost_scalng_factor: 2}\n")
    assert err.key == "layers[1].cost_scalng_factor" and err.line == 3
    assert err.suggestion == "cost_scaling_factor"


def test_a_key_with_no_close_spelling_lists_the_valid_ones():
    err = check("zzz: 1\n")
    assert err.suggestion is None and "update_frequency" in err.message


def test_wrong_type():
    err = check("update_frequency: fast\n")
    assert err.key == "update_frequency" and err.line == 1 and "'fast'" in err.message


def test_valid_document_gives_the_model():
    m = validate(Costmap, load_yaml_text("inflation_layer: {inflation_radius: 0.7}"))
    assert m.inflation_layer.inflation_radius == 0.7 and m.update_frequency == 5.0
