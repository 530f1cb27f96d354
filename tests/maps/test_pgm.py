"""PGM files as netpbm defines them: P5 and P2, 8 and 16 bit, comments, whitespace."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from btnav.core.errors import MapError
from btnav.maps import decode_pgm, encode_pgm, read_image, read_pgm, write_pgm
from btnav.maps.image_io import to_8bit

PIXELS = np.array([[0, 205, 254], [255, 1, 100]], dtype=np.uint8)


def test_p5_round_trip_and_header() -> None:
    raw = encode_pgm(PIXELS)
    assert raw == b"P5\n3 2\n255\n" + PIXELS.tobytes()
    img = decode_pgm(raw)
    assert img.maxval == 255 and not img.plain
    assert img.data.dtype == np.uint8
    np.testing.assert_array_equal(img.data, PIXELS)


def test_p2_round_trip_matches_p5() -> None:
    raw = encode_pgm(PIXELS, plain=True)
    assert raw.startswith(b"P2\n3 2\n255\n")
    img = decode_pgm(raw)
    assert img.plain
    np.testing.assert_array_equal(img.data, PIXELS)


def test_p2_long_rasters_keep_lines_under_70_chars() -> None:
    data = np.arange(65536, dtype=np.uint32).reshape(256, 256) % 65536
    raw = encode_pgm(data, plain=True)
    assert max(len(line) for line in raw.splitlines()) <= 70
    np.testing.assert_array_equal(decode_pgm(raw).data, data)


def test_sixteen_bit_is_big_endian() -> None:
    data = np.array([[0, 1, 256], [65535, 52685, 258]], dtype=np.uint16)
    raw = encode_pgm(data)
    assert raw.startswith(b"P5\n3 2\n65535\n")
    assert raw[-12:] == data.astype(">u2").tobytes()
    img = decode_pgm(raw)
    assert img.maxval == 65535 and img.data.dtype == np.uint16
    np.testing.assert_array_equal(img.data, data)
    # Pillow agrees about the byte order.
    np.testing.assert_array_equal(np.asarray(Image.open(__import__("io").BytesIO(raw))), data)


def test_sixteen_bit_plain() -> None:
    data = np.array([[0, 1000], [65535, 7]], dtype=np.uint16)
    np.testing.assert_array_equal(decode_pgm(encode_pgm(data, plain=True)).data, data)


def test_to_8bit_as_graphicsmagick_q16() -> None:
    wide = np.array([0, 256, 257, 52685, 65278, 65535])
    np.testing.assert_array_equal(to_8bit(wide, 65535), [0, 0, 1, 205, 254, 255])
    np.testing.assert_array_equal(to_8bit(np.array([0, 50, 100]), 100), [0, 127, 255])


@pytest.mark.parametrize(
    "header",
    [
        b"P5\n3 2\n255\n",
        b"P5 3 2 255\n",
        b"P5\n# Created by GIMP version 2.10.30 PNM plug-in\n3 2\n255\n",
        b"P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n3 2\n255\n",
        b"P5#right after the magic\n3#after width\n2\n#before maxval\n255\n",
        b"P5\r\n3\r\n2\r\n255\r",
        b"P5\t3\t2 \n\n 255\t",
        b"P5\n3 2\n255#a comment ends the header\n",
        b"P5\n#\n#\n3 2 # two comments above, one here\n255\n",
    ],
)
def test_header_whitespace_and_comments(header: bytes) -> None:
    img = decode_pgm(header + PIXELS.tobytes())
    np.testing.assert_array_equal(img.data, PIXELS)


def test_comments_inside_a_plain_raster() -> None:
    raw = b"P2\n# c\n3 2\n255\n0 205 # first row\n254\n# second\n255 1 100\n"
    np.testing.assert_array_equal(decode_pgm(raw).data, PIXELS)


def test_trailing_bytes_after_the_raster_are_ignored() -> None:
    img = decode_pgm(encode_pgm(PIXELS) + b"P5\n1 1\n255\n\x00")
    np.testing.assert_array_equal(img.data, PIXELS)


def test_maxval_below_255() -> None:
    raw = b"P5\n3 1\n100\n" + bytes([0, 50, 100])
    img = decode_pgm(raw)
    assert img.maxval == 100
    np.testing.assert_array_equal(img.data, [[0, 50, 100]])


@pytest.mark.parametrize(
    ("raw", "words"),
    [
        (b"P5\n3 2\n255\n" + bytes(5), "truncated"),
        (b"P5\n3 2\n255\n", "need 6 bytes of pixel data, found 0"),
        (b"P5\n3 2\n255", "no pixel data"),
        (b"P5\n3 2\n65535\n" + bytes(11), "truncated"),
        (b"P5\n3", "ends before the height"),
        (b"P5\n3 2", "ends before the maxval"),
        (b"P5\n# never ends", "inside a comment"),
        (b"P5\n3 x 255\n", "expected the height"),
        (b"P5\n0 2\n255\n", "empty"),
        (b"P5\n3 2\n0\n", "maxval"),
        (b"P5\n3 2\n70000\n", "maxval"),
        (b"P5\n3 2\n255x", "whitespace after maxval"),
        (b"P5\n9999999999 2\n255\n", "too many digits"),
        (b"P5\n3 1\n100\n" + bytes([0, 50, 101]), "exceeds maxval"),
        (b"P2\n3 2\n255\n0 1 2 3\n", "truncated"),
        (b"P2\n3 1\n255\n0 -1 2\n", "not a pixel value"),
        (b"P2\n3 1\n255\n0 256 2\n", "exceeds maxval"),
        (b"P2\n2 1\n255\n0 9999999999\n", "not a pixel value"),
        (b"P6\n3 2\n255\n", "not a PGM"),
    ],
)
def test_malformed_files_are_map_errors(raw: bytes, words: str) -> None:
    with pytest.raises(MapError, match=words) as info:
        decode_pgm(raw, "bad.pgm")
    assert info.value.file == "bad.pgm"


def test_huge_claimed_size_does_not_allocate() -> None:
    with pytest.raises(MapError, match="truncated"):
        decode_pgm(b"P5\n999999999 999999999\n65535\n\x00\x00")


def test_read_write_files(tmp_path: Path) -> None:
    path = tmp_path / "m.pgm"
    write_pgm(path, PIXELS)
    np.testing.assert_array_equal(read_pgm(path).data, PIXELS)
    np.testing.assert_array_equal(np.asarray(Image.open(path)), PIXELS)
    with pytest.raises(MapError, match="not found") as info:
        read_pgm(tmp_path / "missing.pgm")
    assert info.value.file == str(tmp_path / "missing.pgm")
    with pytest.raises(MapError, match="directory"):
        read_pgm(tmp_path)


def test_read_image_reduces_16_bit_to_8_bit(tmp_path: Path) -> None:
    path = tmp_path / "wide.pgm"
    write_pgm(path, np.array([[0, 52685, 65535]], dtype=np.uint16))
    image = read_image(path)
    assert image.alpha is None
    np.testing.assert_array_equal(image.grey, [[0, 205, 255]])


def test_encode_refuses_bad_arrays() -> None:
    with pytest.raises(ValueError):
        encode_pgm(np.zeros((0, 3), dtype=np.uint8))
    with pytest.raises(ValueError):
        encode_pgm(np.array([[-1, 3]]))
    with pytest.raises(ValueError):
        encode_pgm(np.array([[300]]), maxval=255)
