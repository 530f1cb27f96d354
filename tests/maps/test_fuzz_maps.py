"""Whatever a user's map files hold, `load_map` raises nothing but a BtnavError."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from btnav.core.errors import BtnavError
from btnav.maps import encode_pgm, load_map

FUZZ = settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)

VALID_YAML = (
    "image: m.pgm\nmode: trinary\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\n"
    "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
)
PIXELS = np.array([[0, 205, 254, 255], [10, 100, 200, 128], [1, 2, 3, 4]], dtype=np.uint8)
VALID_FILES = {
    "p5": encode_pgm(PIXELS),
    "p2": encode_pgm(PIXELS, plain=True),
    "p5_16": encode_pgm(PIXELS.astype(np.uint16) * 257),
    "p2_16": encode_pgm(PIXELS.astype(np.uint16) * 257, plain=True),
}

KEYS = [
    "image",
    "mode",
    "resolution",
    "origin",
    "negate",
    "occupied_thresh",
    "free_thresh",
    "imagee",
    "Mode",
    "ocupied_thresh",
    "origin.x",
    "1",
    "? [k]",
    "<<",
    "",
]
VALUES = [
    "m.pgm",
    "'m.pgm'",
    "missing.pgm",
    "/",
    ".",
    "''",
    "trinary",
    "scale",
    "raw",
    "SCALE",
    "0",
    "1",
    "-1",
    "0.5",
    "1e400",
    "-1e400",
    "9" * 400,
    ".nan",
    ".inf",
    "true",
    "no",
    "~",
    "[0, 0, 0]",
    "[0, 0]",
    "[0, 0, 0, 0]",
    "[.nan, 1, 2]",
    "[[1], {a: 2}, 3]",
    "{a: 1}",
    "[]",
    "{}",
    "!!python/object/apply:os.system ['true']",
    "!!python/name:os.system",
    "!!binary AAAA",
    "!!set {a, b}",
    "!custom 3",
    "&a [1, 2, 3]",
    "*a",
    "2001-12-14",
    "0x10",
    "0o17",
    "1_000",
    '"\\x00"',
    "|\n  block",
    "a" * 5000,
    "/dev/zero",
    "m.pgm/x",
]


def load_quietly(path: Path) -> None:
    with contextlib.suppress(BtnavError):
        load_map(path)


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "m.pgm").write_bytes(VALID_FILES["p5"])
    return tmp_path


@FUZZ
@given(st.binary(max_size=300))
def test_random_bytes_as_the_yaml(folder: Path, data: bytes) -> None:
    (folder / "m.yaml").write_bytes(data)
    load_quietly(folder / "m.yaml")


@FUZZ
@given(st.lists(st.tuples(st.sampled_from(KEYS), st.sampled_from(VALUES)), max_size=10))
def test_wrong_keys_types_tags_and_huge_numbers(folder: Path, pairs: list[tuple[str, str]]) -> None:
    text = VALID_YAML + "".join(f"{k}: {v}\n" for k, v in pairs)
    (folder / "m.yaml").write_text(text)
    load_quietly(folder / "m.yaml")


@FUZZ
@given(st.dictionaries(st.sampled_from(KEYS[:7]), st.sampled_from(VALUES), max_size=7))
def test_replaced_values(folder: Path, replace: dict[str, str]) -> None:
    lines = [
        f"{key}: {replace.get(key, value)}"
        for key, value in (line.split(": ", 1) for line in VALID_YAML.splitlines())
    ]
    (folder / "m.yaml").write_text("\n".join(lines) + "\n")
    load_quietly(folder / "m.yaml")


@FUZZ
@given(st.binary(max_size=400), st.sampled_from(["", "P5", "P2", "P5\n4 3\n255\n", "\x89PNG"]))
def test_random_bytes_as_the_image(folder: Path, data: bytes, prefix: str) -> None:
    (folder / "m.yaml").write_text(VALID_YAML)
    (folder / "m.pgm").write_bytes(prefix.encode("latin-1") + data)
    load_quietly(folder / "m.yaml")


@FUZZ
@given(st.sampled_from(sorted(VALID_FILES)), st.data())
def test_truncated_pgm_files(folder: Path, kind: str, data: st.DataObject) -> None:
    raw = VALID_FILES[kind]
    # A plain file cut inside its last number still holds a (different) complete image.
    last = raw.rstrip().rfind(b" ") if kind.startswith("p2") else len(raw) - 1
    cut = data.draw(st.integers(min_value=0, max_value=last))
    (folder / "m.yaml").write_text(VALID_YAML)
    (folder / "m.pgm").write_bytes(raw[:cut])
    with pytest.raises(BtnavError):
        load_map(folder / "m.yaml")


HEADER_PARTS = [
    b"P5",
    b"P2",
    b" ",
    b"\n",
    b"\r",
    b"\t",
    b"#c\n",
    b"#",
    b"4",
    b"3",
    b"255",
    b"65535",
    b"0",
    b"99999999999",
    b"-1",
    b"x",
    b"\x00",
    b"\xff",
]


@FUZZ
@given(st.lists(st.sampled_from(HEADER_PARTS), max_size=14), st.binary(max_size=60))
def test_fuzzed_pgm_headers(folder: Path, parts: list[bytes], raster: bytes) -> None:
    (folder / "m.yaml").write_text(VALID_YAML)
    (folder / "m.pgm").write_bytes(b"P5" + b"".join(parts) + raster)
    load_quietly(folder / "m.yaml")


def _png_bytes() -> bytes:
    buf = io.BytesIO()
    Image.fromarray(PIXELS).save(buf, format="PNG")
    return buf.getvalue()


PNG = _png_bytes()


@FUZZ
@given(st.integers(min_value=0, max_value=len(PNG) - 1), st.binary(max_size=8))
def test_truncated_and_damaged_png(folder: Path, cut: int, junk: bytes) -> None:
    (folder / "m.yaml").write_text(VALID_YAML.replace("m.pgm", "m.png"))
    (folder / "m.png").write_bytes(PNG[:cut] + junk + PNG[cut + len(junk) :])
    load_quietly(folder / "m.yaml")
