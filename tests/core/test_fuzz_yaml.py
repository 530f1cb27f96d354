"""Whatever bytes a user hands the YAML loader, only a BtnavError comes back out."""

from __future__ import annotations

import contextlib

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from btnav.core.errors import BtnavError
from btnav.core.yaml_io import load_yaml_text

FRAGMENTS = [
    "a: 1\n",
    "- x\n",
    "  b: [1, 2]\n",
    "!!python/object/apply:os.system ['id']\n",
    "&x [1]\n",
    "*x\n",
    "? [k]\n",
    ": v\n",
    "{",
    "}",
    "[",
    "]",
    "'",
    '"',
    "\t",
    "%YAML 1.1\n",
    "---\n",
    "...\n",
    "9" * 400 + "\n",
    "<<: *x\n",
    "!!binary AAAA\n",
    ".nan\n",
    "~\n",
    "\\x00",
]


def load_ok(data: bytes | str) -> None:
    with contextlib.suppress(BtnavError):
        load_yaml_text(data, "fuzz.yaml")


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.binary(max_size=400))
def test_random_bytes(data: bytes) -> None:
    load_ok(data)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(FRAGMENTS), max_size=30))
def test_yaml_looking_fragments(parts: list[str]) -> None:
    load_ok("".join(parts))


@settings(max_examples=100, deadline=None)
@given(st.integers(min_value=0, max_value=600))
def test_truncated_nav2_params(cut: int) -> None:
    from pathlib import Path

    text = (Path(__file__).resolve().parents[3] / "shared/nav2/params/nav2_params.yaml").read_text()
    load_ok(text[: cut * 30])
