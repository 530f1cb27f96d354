"""Whatever a world file holds, loading it raises nothing but a `BtnavError`."""

from __future__ import annotations

import copy
import math
import re
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from btnav.core.errors import BtnavError
from btnav.core.resources import bundled_dir
from btnav.core.yaml_io import load_yaml, to_plain
from btnav.sim.world import World

OFFICE = bundled_dir("worlds") / "small_office.yaml"
OFFICE_TEXT = OFFICE.read_text()
OFFICE_DATA = to_plain(load_yaml(OFFICE))

FUZZ = settings(
    max_examples=120,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


def load_only_btnav_errors(path: Path) -> None:
    try:
        World.from_file(path, seed=0)
    except BtnavError as err:
        assert str(err)  # a message a user can read
        assert isinstance(err.file, str) or err.file is None


@pytest.fixture(scope="module")
def scratch(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("fuzz") / "world.yaml"


def _paths(data: Any, prefix: tuple = ()) -> list[tuple]:
    out = [prefix]
    if isinstance(data, dict):
        for k, v in data.items():
            out += _paths(v, (*prefix, k))
    elif isinstance(data, list):
        for i, v in enumerate(data):
            out += _paths(v, (*prefix, i))
    return out


PATHS = _paths(OFFICE_DATA)[1:]

numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.sampled_from([0, -0.0, 1e-300, -1e-300, 1e300, -1e300, 1e5, -1e5, 2**63, 10**400]),
)
scalars = st.one_of(st.none(), st.booleans(), numbers, st.text(max_size=12))
values = st.recursive(
    scalars,
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=3)
    ),
    max_leaves=12,
)


def _set(data: Any, path: tuple, value: Any, mode: str) -> Any:
    data = copy.deepcopy(data)
    node = data
    for part in path[:-1]:
        node = node[part]
    last = path[-1]
    if mode == "delete" and isinstance(node, dict):
        del node[last]
    elif mode == "extra" and isinstance(node, dict):
        node[f"{last}_x"] = value
    else:
        node[last] = value
    return data


@FUZZ
@given(st.binary(max_size=400))
def test_random_bytes(scratch, blob):
    scratch.write_bytes(blob)
    load_only_btnav_errors(scratch)


@FUZZ
@given(st.integers(min_value=0, max_value=len(OFFICE_TEXT)))
def test_truncated_office(scratch, cut):
    scratch.write_text(OFFICE_TEXT[:cut])
    load_only_btnav_errors(scratch)


@FUZZ
@given(
    st.sampled_from(PATHS),
    values,
    st.sampled_from(["replace", "replace", "replace", "delete", "extra"]),
)
def test_wrong_value_at_a_random_key(scratch, path, value, mode):
    data = _set(OFFICE_DATA, path, value, mode)
    scratch.write_text(yaml.safe_dump(data, allow_unicode=True))
    load_only_btnav_errors(scratch)


def _get(data: Any, path: tuple) -> Any:
    for part in path:
        data = data[part]
    return data


NUMBER_PATHS = [
    p
    for p in PATHS
    if isinstance(_get(OFFICE_DATA, p), int | float) and not isinstance(_get(OFFICE_DATA, p), bool)
]


@FUZZ
@given(st.sampled_from(NUMBER_PATHS), numbers)
def test_extreme_number_at_a_random_number(scratch, path, number):
    """Sizes, coordinates and limits at their extremes: errors or a working world."""
    data = _set(OFFICE_DATA, path, number, "replace")
    scratch.write_text(yaml.safe_dump(data))
    load_only_btnav_errors(scratch)


TAGS = [
    "!!python/object/apply:os.system ['true']",
    "!!python/object:collections.OrderedDict {}",
    "!!python/name:os.system",
    "!!binary aGVsbG8=",
    "!!set {a: null}",
    "!custom 3",
    "&a [1, *a]",
    "&b {k: *b}",
    "!!float 1e999",
    "!!int 0x7fffffffffffffffffff",
    "*undefined",
]
VALUE_LINES = [
    i for i, line in enumerate(OFFICE_TEXT.splitlines()) if re.match(r"^\s*[\w-].*: \S", line)
]


@FUZZ
@given(st.sampled_from(VALUE_LINES), st.sampled_from(TAGS))
def test_object_tags_and_aliases(scratch, line_no, tag):
    lines = OFFICE_TEXT.splitlines()
    head, _, _ = lines[line_no].partition(": ")
    lines[line_no] = f"{head}: {tag}"
    scratch.write_text("\n".join(lines) + "\n")
    load_only_btnav_errors(scratch)


def test_the_office_itself_loads():
    assert math.isclose(World.from_file(OFFICE).robot_pose.x, 1.0)
