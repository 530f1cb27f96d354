"""Whatever a params file holds, loading it either succeeds or raises a `BtnavError`.

Random bytes, truncated copies of Nav2's file, wrong types and huge numbers at
random keys, renamed keys and object tags: nothing else may escape `load_params`.
"""

from __future__ import annotations

import contextlib
import tempfile
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from btnav.core.errors import BtnavError
from btnav.core.yaml_io import YamlMap, load_yaml
from btnav.params import ParamsFile, apply_overrides, load_params, load_params_doc
from btnav.params.tree import copy_tree

NAV2 = (
    Path(__file__).resolve().parents[2].parent / "shared" / "nav2" / "params" / "nav2_params.yaml"
)
FUZZ = settings(
    max_examples=120,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)

pytestmark = pytest.mark.skipif(not NAV2.is_file(), reason="Nav2's params file is missing")


def nav2_text() -> str:
    return NAV2.read_text()


def nav2_blocks() -> list[list[str]]:
    """Nav2's file cut into its top-level server sections (each a params file of its own).

    Line-level mutations go into one section at a time: the same cases at a
    fraction of the YAML parsing time of the whole file.
    """
    blocks: list[list[str]] = []
    for line in nav2_text().splitlines(keepends=True):
        if line[:1].isalpha() or not blocks:
            blocks.append([])
        blocks[-1].append(line)
    return blocks


def nav2_doc() -> YamlMap:
    return load_yaml(NAV2)


def paths_of(node: Any, prefix: tuple = ()) -> list[tuple]:
    """Every path to a key or item in the document."""
    out = []
    items = (
        node.items()
        if isinstance(node, dict)
        else enumerate(node)
        if isinstance(node, list)
        else []
    )
    for key, value in items:
        out.append((*prefix, key))
        out += paths_of(value, (*prefix, key))
    return out


_DOC = nav2_doc() if NAV2.is_file() else YamlMap()
_PATHS = paths_of(_DOC)

values = st.recursive(
    st.one_of(
        st.none(),
        st.booleans(),
        st.integers(min_value=-(10**400), max_value=10**400),
        st.floats(allow_nan=True, allow_infinity=True),
        st.text(max_size=20),
        st.sampled_from(["KEEPOUT_ZONE_ENABLED", "[[0.1, 0.2]]", "$(find-pkg-share x)", "nan"]),
    ),
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=8,
)


def load_text(text: str | bytes) -> ParamsFile | None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "params.yaml"
        path.write_bytes(text if isinstance(text, bytes) else text.encode())
        try:
            return load_params(path)
        except BtnavError:
            return None


def load_doc(doc: Any) -> ParamsFile | None:
    try:
        return load_params_doc(doc, "fuzz.yaml")
    except BtnavError:
        return None


@FUZZ
@given(st.binary(max_size=400))
def test_random_bytes(data: bytes) -> None:
    load_text(data)


@FUZZ
@given(st.data())
def test_truncated_nav2_file(data: st.DataObject) -> None:
    text = nav2_text()
    cut = data.draw(st.integers(min_value=0, max_value=len(text)))
    load_text(text[:cut])


@FUZZ
@given(st.data())
def test_lines_of_nav2_file_dropped_or_duplicated(data: st.DataObject) -> None:
    lines = data.draw(st.sampled_from(nav2_blocks()))[:]
    i = data.draw(st.integers(min_value=0, max_value=len(lines) - 1))
    if data.draw(st.booleans()):
        del lines[i]
    else:
        lines.insert(i, lines[i])
    load_text("".join(lines))


@FUZZ
@given(st.data(), values)
def test_wrong_value_at_a_random_key(data: st.DataObject, value: Any) -> None:
    doc = copy_tree(_DOC)
    path = data.draw(st.sampled_from(_PATHS))
    node = doc
    for part in path[:-1]:
        node = node[part]
    node[path[-1]] = copy_tree(value)
    load_doc(doc)


@FUZZ
@given(st.data(), st.one_of(st.text(max_size=12), st.integers(), st.none(), st.booleans()))
def test_random_key_renamed(data: st.DataObject, new_key: Any) -> None:
    doc = copy_tree(_DOC)
    path = data.draw(st.sampled_from([p for p in _PATHS if not isinstance(p[-1], int)]))
    node = doc
    for part in path[:-1]:
        node = node[part]
    value = node.pop(path[-1])
    node[new_key] = value
    load_doc(doc)


@FUZZ
@given(
    st.data(),
    st.sampled_from(
        [
            "!!python/object/apply:os.system ['echo pwned']",
            "!!python/name:os.system",
            "!!binary aGVsbG8=",
            "!custom 3",
            "1e400",
            "9" * 400,
            "-.inf",
            ".nan",
            "&a [*a]",
            "{a: [1, 2], b: {c: d}}",
        ]
    ),
)
def test_odd_scalars_and_tags_in_place_of_a_value(data: st.DataObject, replacement: str) -> None:
    blocks = [b for b in nav2_blocks() if any(": " in line for line in b)]
    lines = data.draw(st.sampled_from(blocks))[:]
    candidates = [
        i for i, line in enumerate(lines) if ": " in line and not line.strip().startswith("#")
    ]
    i = data.draw(st.sampled_from(candidates))
    key = lines[i].split(": ", 1)[0]
    lines[i] = f"{key}: {replacement}\n"
    load_text("".join(lines))


@FUZZ
@given(st.dictionaries(st.text(min_size=1, max_size=30), values, max_size=3))
def test_random_overrides(overrides: dict[str, Any]) -> None:
    params = load_params_doc(copy_tree(_DOC), NAV2)
    with contextlib.suppress(BtnavError):
        apply_overrides(params, overrides)


def test_an_object_tag_is_refused_not_run(tmp_path: Path) -> None:
    marker = tmp_path / "ran"
    text = nav2_text().replace(
        "alpha1: 0.2", f"alpha1: !!python/object/apply:os.system ['touch {marker}']"
    )
    assert load_text(text) is None
    assert not marker.exists()
