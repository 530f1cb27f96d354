"""The YAML loader: lines for every key and item, and no object tags, ever."""

from __future__ import annotations

import pytest

from btnav.core.errors import BtnavError, YamlError
from btnav.core.yaml_io import line_at, load_yaml, load_yaml_text


def test_nav2_params_lines_point_at_the_keys(nav2_params_file):
    doc = load_yaml(nav2_params_file)
    lines = nav2_params_file.read_text().splitlines()
    for path in (
        ["controller_server", "ros__parameters", "controller_frequency"],
        [
            "local_costmap",
            "local_costmap",
            "ros__parameters",
            "inflation_layer",
            "inflation_radius",
        ],
        ["amcl", "ros__parameters", "alpha3"],
    ):
        line = line_at(doc, path)
        assert lines[line - 1].strip().startswith(path[-1] + ":"), (path, line)
    critics = ["controller_server", "ros__parameters", "FollowPath", "critics"]
    assert '"GoalCritic"' in lines[line_at(doc, [*critics, 2]) - 1]


@pytest.mark.parametrize(
    "text",
    [
        "a: !!python/object/apply:os.system ['echo hi']",
        "a: !!python/name:os.system",
        "!!python/object:collections.OrderedDict {}",
        "a: !custom 3",
        "a: !!binary aGVsbG8=",
        "a: !!set {x, y}",
    ],
)
def test_object_and_custom_tags_are_refused(text):
    with pytest.raises(YamlError, match="not allowed") as info:
        load_yaml_text(text, "evil.yaml")
    assert info.value.file == "evil.yaml" and info.value.line == 1


def test_syntax_error_names_the_line():
    with pytest.raises(YamlError) as info:
        load_yaml_text("a: 1\nb: [1, 2\nc: 3\n", "bad.yaml")
    assert info.value.line == 2 and "bad.yaml" in str(info.value)


PARAMS_HEAD = """\
controller_server:
  ros__parameters:
    controller_frequency: 20.0
    min_x_velocity_threshold: 0.001
    progress_checker_plugins: ["progress_checker"]
    goal_checker_plugins: ["general_goal_checker"]
    controller_plugins: ["FollowPath"]
"""


@pytest.mark.parametrize(
    "old, new, message",
    [
        (  # a list whose ']' is missing: PyYAML notices on the next line
            '["progress_checker"]',
            '["progress_checker"',
            "invalid YAML: the '[' opened on this line is not closed "
            "(expected ',' or ']', but got '<scalar>' at line 6)",
        ),
        (  # a quote that never closes: PyYAML notices at the end of the file
            'controller_plugins: ["FollowPath"]',
            'controller_plugins: ["FollowPath]',
            "invalid YAML: the quote opened on this line is not closed "
            "(found unexpected end of stream)",
        ),
        (  # a line indented too far
            "    min_x_velocity_threshold",
            "      min_x_velocity_threshold",
            "invalid YAML: mapping values are not allowed here "
            "(is this line indented too far, or does it hold an unquoted ': '?)",
        ),
        (  # a line indented too little
            "    min_x_velocity_threshold",
            "   min_x_velocity_threshold",
            "invalid YAML: expected <block end>, but found '<block mapping start>' "
            "(check the indentation of this line)",
        ),
        (  # no space after the colon: the text runs on into the next key
            "controller_frequency: 20.0",
            "controller_frequency:20.0",
            "invalid YAML: the text on this line runs on into line 4 "
            "(a key needs ': ', a colon and a space, before its value)",
        ),
        (  # a tab in the indentation
            "    min_x_velocity_threshold",
            "\tmin_x_velocity_threshold",
            "invalid YAML: found character '\\t' that cannot start any token "
            "(YAML indents with spaces, not tabs)",
        ),
    ],
)
def test_a_syntax_error_names_the_broken_line_not_the_next(old, new, message):
    assert old in PARAMS_HEAD
    broken = PARAMS_HEAD.replace(old, new, 1)
    line = next(n for n, text in enumerate(broken.splitlines(), 1) if new in text)
    with pytest.raises(YamlError) as info:
        load_yaml_text(broken, "my_params.yaml")
    assert str(info.value) == f"my_params.yaml:{line}: {message}"


def test_duplicate_key_names_both_lines():
    with pytest.raises(YamlError, match="first at line 1") as info:
        load_yaml_text("x: 1\ny: 2\nx: 3\n")
    assert info.value.line == 3


def test_dates_stay_strings_and_numbers_are_numbers():
    doc = load_yaml_text("d: 2024-01-01\nf: 1.0e-10\ni: 0x10\nb: true\nn: ~\n")
    assert doc == {"d": "2024-01-01", "f": 1e-10, "i": 16, "b": True, "n": None}


def test_huge_integers_and_deep_nesting_are_errors_not_crashes():
    with pytest.raises(YamlError):
        load_yaml_text("x: " + "9" * 5000)
    with pytest.raises(BtnavError):
        load_yaml_text("[" * 100_000 + "]" * 100_000)


def test_alias_bombs_are_refused():
    bomb = "a: &a [x, x]\n" + "".join(
        f"{c}: &{c} [*{p}, *{p}, *{p}, *{p}]\n"
        for p, c in zip("abcdefghijklmnopqrstuvwxy", "bcdefghijklmnopqrstuvwxyz", strict=True)
    )
    bomb += "z2: [" + ", ".join(["*z"] * 1100) + "]\n"
    with pytest.raises(YamlError, match="aliases"):
        load_yaml_text(bomb)


def test_missing_file_and_binary_garbage(tmp_path):
    with pytest.raises(YamlError, match="not found") as info:
        load_yaml(tmp_path / "nope.yaml")
    assert "nope.yaml" in str(info.value)
    bad = tmp_path / "bin.yaml"
    bad.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(YamlError, match="UTF-8"):
        load_yaml(bad)
