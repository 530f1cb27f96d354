"""map_server's YAML + image semantics: modes, negate, thresholds, alpha, errors, saving."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from PIL import Image

from btnav.core.errors import BtnavError, MapError
from btnav.core.geometry import Pose2D
from btnav.maps import (
    MapMetadata,
    OccupancyGrid,
    encode_pgm,
    load_map,
    map_yaml_text,
    read_map,
    read_map_metadata,
    read_pgm,
    save_map,
)

ALL_LEVELS = np.arange(256, dtype=np.uint8).reshape(16, 16)


def write_map(
    folder: Path,
    *,
    pixels: np.ndarray | None = None,
    image: str = "m.pgm",
    yaml_name: str = "m.yaml",
    **keys: object,
) -> Path:
    """A map YAML (keys override the defaults; None drops a key) beside its PGM."""
    fields: dict[str, object] = {
        "image": image,
        "mode": "trinary",
        "resolution": 0.05,
        "origin": "[0.0, 0.0, 0.0]",
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    fields.update(keys)
    text = "".join(f"{k}: {v}\n" for k, v in fields.items() if v is not None)
    path = folder / yaml_name
    path.write_text(text)
    if pixels is not None:
        (folder / image).write_bytes(encode_pgm(pixels))
    return path


def levels(grid: OccupancyGrid) -> np.ndarray:
    """The 16x16 all-levels picture back in image order, flattened: value per grey level."""
    return grid.data[::-1].ravel()


# --- reading: modes, thresholds, negate ---------------------------------------------------


def test_trinary_thresholds_are_inclusive(tmp_path: Path) -> None:
    grid = load_map(write_map(tmp_path, pixels=ALL_LEVELS))
    values = levels(grid)
    n = 1.0 - np.arange(256) / 255.0
    assert (values[n >= 0.65 + 1e-6] == 100).all()
    assert (values[n <= 0.196 - 1e-6] == 0).all()
    assert (values[(n > 0.196 + 1e-6) & (n < 0.65 - 1e-6)] == -1).all()
    assert values[205] == -1 and values[254] == 0 and values[0] == 100
    # Exactly at the thresholds (1.0 and 0.0) map_server's >= and <= hold.
    edge = load_map(write_map(tmp_path, pixels=ALL_LEVELS, occupied_thresh=1.0, free_thresh=0.0))
    assert levels(edge)[0] == 100 and levels(edge)[255] == 0
    assert (levels(edge)[1:255] == -1).all()


def test_free_wins_when_thresholds_are_equal(tmp_path: Path) -> None:
    grid = load_map(write_map(tmp_path, pixels=ALL_LEVELS, occupied_thresh=0.5, free_thresh=0.5))
    assert set(levels(grid).tolist()) == {0, 100}


def test_negate_swaps_black_and_white(tmp_path: Path) -> None:
    plain = levels(load_map(write_map(tmp_path, pixels=ALL_LEVELS)))
    negated = levels(load_map(write_map(tmp_path, pixels=ALL_LEVELS, negate=1)))
    np.testing.assert_array_equal(negated, plain[::-1])
    assert negated[0] == 0 and negated[255] == 100
    for spelling in ("true", "True", "yes", 5):
        again = load_map(write_map(tmp_path, pixels=ALL_LEVELS, negate=spelling))
        np.testing.assert_array_equal(levels(again), negated)
    for spelling in ("false", 0):
        again = load_map(write_map(tmp_path, pixels=ALL_LEVELS, negate=spelling))
        np.testing.assert_array_equal(levels(again), plain)


def test_scale_is_linear_between_the_thresholds(tmp_path: Path) -> None:
    grid = load_map(
        write_map(tmp_path, pixels=ALL_LEVELS, mode="scale", occupied_thresh=0.65, free_thresh=0.25)
    )
    values = levels(grid)
    n = 1.0 - np.arange(256) / 255.0
    between = (n > 0.25 + 1e-6) & (n < 0.65 - 1e-6)
    exact = (n[between] - 0.25) / 0.4 * 100.0
    # Rounded to the nearest; map_server works in float32, so exact .5 ties may go either way.
    assert np.abs(values[between] - exact).max() <= 0.5 + 1e-4
    assert (values[n >= 0.65] == 100).all() and (values[n <= 0.25] == 0).all()
    assert -1 not in values  # scale mode has no unknown without alpha


def test_scale_with_unit_thresholds_reads_percentages(tmp_path: Path) -> None:
    grid = load_map(
        write_map(tmp_path, pixels=ALL_LEVELS, mode="scale", occupied_thresh=1, free_thresh=0)
    )
    np.testing.assert_array_equal(levels(grid), np.floor((255 - np.arange(256)) / 2.55 + 0.5))


def test_raw_takes_values_and_ignores_negate(tmp_path: Path) -> None:
    for negate in (0, 1):
        grid = load_map(write_map(tmp_path, pixels=ALL_LEVELS, mode="raw", negate=negate))
        values = levels(grid)
        np.testing.assert_array_equal(values[:101], np.arange(101))
        assert (values[101:] == -1).all()  # map_server: above 100 is unknown


def test_mode_is_case_insensitive_and_defaults_to_trinary(tmp_path: Path) -> None:
    assert read_map(write_map(tmp_path, pixels=ALL_LEVELS, mode="Scale")).metadata.mode == "scale"
    loaded = read_map(write_map(tmp_path, pixels=ALL_LEVELS, mode=None))
    assert loaded.metadata.mode == "trinary"


def test_grid_row_zero_is_the_bottom_of_the_picture(tmp_path: Path) -> None:
    pixels = np.full((3, 4), 254, dtype=np.uint8)
    pixels[0, 0] = 0  # top-left pixel occupied
    grid = load_map(write_map(tmp_path, pixels=pixels, origin="[1.0, 2.0, 0.5]"))
    assert grid.data[2, 0] == 100 and grid.data.sum() == 100
    assert grid.origin == Pose2D(1.0, 2.0, 0.5)
    assert (grid.width, grid.height) == (4, 3)


def test_image_paths_relative_to_the_yaml_or_absolute(tmp_path: Path) -> None:
    (tmp_path / "img").mkdir()
    (tmp_path / "img" / "a.pgm").write_bytes(encode_pgm(ALL_LEVELS))
    rel = write_map(tmp_path, image="img/a.pgm", yaml_name="rel.yaml")
    absolute = write_map(tmp_path, image=str(tmp_path / "img" / "a.pgm"), yaml_name="abs.yaml")
    assert read_map(rel).image_path == tmp_path / "img" / "a.pgm"
    assert load_map(rel) == load_map(absolute)


def test_png_grey_alpha_and_colour(tmp_path: Path) -> None:
    grey = np.array([[0, 254, 205, 0]], dtype=np.uint8)
    alpha = np.array([[255, 255, 255, 0]], dtype=np.uint8)
    Image.fromarray(np.stack([grey, alpha], -1), "LA").save(tmp_path / "m.png")
    for mode, free, occupied, middle in (("trinary", 0.196, 0.65, -1), ("scale", 0, 1, 20)):
        path = write_map(
            tmp_path, image="m.png", mode=mode, free_thresh=free, occupied_thresh=occupied
        )
        grid = load_map(path)
        expected = [100, 0, middle, -1]  # transparent -> unknown
        np.testing.assert_array_equal(grid.data, [expected])
    raw = load_map(write_map(tmp_path, image="m.png", mode="raw"))
    np.testing.assert_array_equal(raw.data, [[0, -1, -1, 0]])  # raw ignores alpha
    rgb = np.array([[[255, 0, 0], [10, 10, 10], [255, 255, 255]]], dtype=np.uint8)
    Image.fromarray(rgb, "RGB").save(tmp_path / "c.png")
    grid = load_map(write_map(tmp_path, image="c.png"))
    np.testing.assert_array_equal(grid.data, [[100, 100, 0]])  # red: luma 76 -> dark


def test_sixteen_bit_png_and_pgm(tmp_path: Path) -> None:
    wide = np.array([[0, 52685, 65535]], dtype=np.uint16)
    Image.fromarray(wide).save(tmp_path / "w.png")
    (tmp_path / "w.pgm").write_bytes(encode_pgm(wide))
    for name in ("w.png", "w.pgm"):
        grid = load_map(write_map(tmp_path, image=name))
        np.testing.assert_array_equal(grid.data, [[100, -1, 0]])


def test_plain_pgm_with_comments_loads(tmp_path: Path) -> None:
    (tmp_path / "p.pgm").write_bytes(b"P2\n# made by hand\n3 1 # w h\n255\n0 205\n# x\n254\n")
    np.testing.assert_array_equal(load_map(write_map(tmp_path, image="p.pgm")).data, [[100, -1, 0]])


# --- reading: errors -------------------------------------------------------------------------


def test_misspelt_key_names_file_line_and_spelling(tmp_path: Path) -> None:
    path = write_map(tmp_path, pixels=ALL_LEVELS, occupied_thresh=None, ocupied_thresh=0.65)
    with pytest.raises(MapError) as info:
        load_map(path)
    err = info.value
    assert err.file == str(path)
    assert err.line == 7  # the misspelt key is written last
    assert err.key == "ocupied_thresh"
    assert err.suggestion == "occupied_thresh"
    assert f"{path}:7" in str(err) and "did you mean 'occupied_thresh'" in str(err)


def test_misspelt_mode_suggests_the_mode(tmp_path: Path) -> None:
    path = write_map(tmp_path, pixels=ALL_LEVELS, mode="trinay")
    with pytest.raises(MapError, match="did you mean 'trinary'") as info:
        load_map(path)
    assert info.value.line == 2 and info.value.key == "mode"


@pytest.mark.parametrize(
    ("keys", "key", "words"),
    [
        ({"resolution": None}, "resolution", "missing"),
        ({"resolution": 0}, "resolution", "greater than 0"),
        ({"resolution": ".nan"}, "resolution", "finite"),
        ({"resolution": "true"}, "resolution", "not a boolean"),
        ({"origin": "[1, 2]"}, "origin", "3 numbers"),
        ({"origin": "[1, 2, x]"}, "origin", "number"),
        ({"origin": 5}, "origin", "3 numbers"),
        ({"negate": 0.5}, "negate", "0 or 1"),
        ({"image": "''"}, "image", "empty"),
        ({"image": "[a]"}, "image", "string"),
        ({"occupied_thresh": 1.5}, "occupied_thresh", "between 0.0 and 1.0"),
        ({"free_thresh": -0.1}, "free_thresh", "between 0.0 and 1.0"),
        ({"free_thresh": 0.9}, "free_thresh", "above occupied_thresh"),
        ({"mode": 3}, "mode", "one of"),
    ],
)
def test_bad_values_are_located(tmp_path: Path, keys: dict, key: str, words: str) -> None:
    path = write_map(tmp_path, pixels=ALL_LEVELS, **keys)
    with pytest.raises(MapError, match=words) as info:
        load_map(path)
    assert info.value.file == str(path)
    assert info.value.key is not None and info.value.key.startswith(key)
    assert info.value.line is not None


def test_missing_yaml(tmp_path: Path) -> None:
    with pytest.raises(MapError, match="not found") as info:
        load_map(tmp_path / "nope.yaml")
    assert info.value.file == str(tmp_path / "nope.yaml")


def test_missing_image_names_its_path_and_the_yaml_line(tmp_path: Path) -> None:
    path = write_map(tmp_path, image="gone.pgm")
    with pytest.raises(MapError) as info:
        load_map(path)
    assert str(tmp_path / "gone.pgm") in str(info.value)
    assert info.value.file == str(path) and info.value.line == 1 and info.value.key == "image"


@pytest.mark.parametrize(
    ("content", "words"),
    [
        (b"P5\n16 16\n255\n" + bytes(100), "truncated"),
        (b"", "empty"),
        (b"\x89PNG\r\n\x1a\n garbage", "cannot read the image"),
        (b"hello, not an image", "cannot read the image"),
    ],
)
def test_corrupt_images_name_the_image(tmp_path: Path, content: bytes, words: str) -> None:
    (tmp_path / "bad.img").write_bytes(content)
    with pytest.raises(MapError, match=words) as info:
        load_map(write_map(tmp_path, image="bad.img"))
    assert info.value.file == str(tmp_path / "bad.img")


def test_yaml_that_is_not_a_mapping(tmp_path: Path) -> None:
    for text in ("- image: m.pgm\n", "just text\n", ""):
        (tmp_path / "m.yaml").write_text(text)
        with pytest.raises(MapError, match="mapping of keys"):
            load_map(tmp_path / "m.yaml")


def test_object_tags_are_refused(tmp_path: Path) -> None:
    (tmp_path / "m.yaml").write_text("image: !!python/object/apply:os.system ['true']\n")
    with pytest.raises(MapError, match="not allowed") as info:
        load_map(tmp_path / "m.yaml")
    assert info.value.line == 1


def test_without_pillow_png_asks_for_the_viz_extra(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    Image.fromarray(ALL_LEVELS).save(tmp_path / "m.png")
    write_map(tmp_path, image="m.png", yaml_name="png.yaml")
    write_map(tmp_path, pixels=ALL_LEVELS, yaml_name="pgm.yaml")
    monkeypatch.setitem(sys.modules, "PIL", None)  # `from PIL import Image` now fails
    with pytest.raises(BtnavError, match=r"pip install btnav\[viz\]"):
        load_map(tmp_path / "png.yaml")
    assert load_map(tmp_path / "pgm.yaml").width == 16  # PGM needs no Pillow
    grid = OccupancyGrid(np.zeros((2, 2), np.int8), 0.1)
    with pytest.raises(BtnavError, match=r"pip install btnav\[viz\]"):
        save_map(grid, tmp_path / "s.yaml", image_format="png")


def test_read_map_metadata_alone(tmp_path: Path) -> None:
    meta = read_map_metadata(write_map(tmp_path, negate="true", origin="[1, -2, 0.5]"))
    assert meta == MapMetadata(
        image="m.pgm",
        mode="trinary",
        resolution=0.05,
        origin=(1.0, -2.0, 0.5),
        negate=True,
        occupied_thresh=0.65,
        free_thresh=0.196,
    )


# --- saving -----------------------------------------------------------------------------------


def test_saved_files_are_what_map_saver_writes(tmp_path: Path) -> None:
    data = np.array([[0, 100, -1], [0, 25, 26], [64, 65, 101]], dtype=np.int8)
    grid = OccupancyGrid(data, 0.05, Pose2D(-10.0, -10.0, 0.0))
    yaml_path, image = save_map(grid, tmp_path / "office.yaml")
    assert image == tmp_path / "office.pgm"
    assert yaml_path.read_text() == (
        "image: office.pgm\n"
        "mode: trinary\n"
        "resolution: 0.050\n"
        "origin: [-10.000, -10.000, 0]\n"
        "negate: 0\n"
        "occupied_thresh: 0.65\n"
        "free_thresh: 0.196"
    )
    # free <= rint(0.25*100) -> 254, occupied >= rint(0.65*100) -> 0, the rest 205;
    # image rows run top-down, grid rows bottom-up.
    expected = np.array([[205, 0, 205], [254, 254, 205], [254, 0, 205]], dtype=np.uint8)
    assert image.read_bytes() == b"P5\n3 3\n255\n" + expected.tobytes()


def test_scale_and_raw_yaml(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.array([[0, 50, 100, -1]], np.int8), 0.1, Pose2D(1.5, 0.0, 1.0))
    yaml_path, image = save_map(
        grid, tmp_path / "s", mode="scale", free_thresh=0.0, occupied_thresh=1.0
    )
    assert (yaml_path, image) == (tmp_path / "s.yaml", tmp_path / "s.png")
    assert yaml_path.read_text().splitlines() == [
        "image: s.png",
        "mode: scale",
        "resolution: 0.100",
        "origin: [1.500, 0.000, 1]",
        "negate: 0",
        "occupied_thresh: 1.000",
        "free_thresh: 0.000",
    ]
    rgba = np.asarray(Image.open(image))
    np.testing.assert_array_equal(rgba[0, :, 3], [255, 255, 255, 0])
    np.testing.assert_array_equal(rgba[0, :3, 0], [255, 127, 0])
    assert load_map(yaml_path) == grid
    yaml_path, image = save_map(grid, tmp_path / "r.yaml", mode="raw")
    assert image.suffix == ".pgm"
    np.testing.assert_array_equal(read_pgm(image).data, [[0, 50, 100, 255]])
    assert load_map(yaml_path) == grid


def test_values_that_do_not_survive_map_saver(tmp_path: Path) -> None:
    """Documented losses, the same as Nav2's: trinary keeps 3 classes, scale re-maps."""
    data = np.array([[10, 40, 70, 120]], dtype=np.int8)
    grid = OccupancyGrid(data, 0.1)
    np.testing.assert_array_equal(
        load_map(save_map(grid, tmp_path / "t.yaml")[0]).data, [[0, -1, 100, -1]]
    )
    scaled = load_map(save_map(grid, tmp_path / "s.yaml", mode="scale")[0]).data
    # 40 is written as grey 153, read back with thresholds 0.25/0.65 as 37.
    np.testing.assert_array_equal(scaled, [[0, 37, 100, -1]])


def test_numbers_map_saver_would_round_are_kept_exact(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.zeros((2, 2), np.int8), 0.0125, Pose2D(0.0001, -3.25, math.pi / 2))
    text = save_map(grid, tmp_path / "m.yaml")[0].read_text()
    assert "resolution: 0.0125\n" in text
    assert "origin: [0.0001, -3.250, 1.5707963267948966]" in text
    assert load_map(tmp_path / "m.yaml") == grid
    # A yaw read from a YAML keeps its short spelling when saved again.
    loaded = load_map(write_map(tmp_path, pixels=ALL_LEVELS, origin="[0, 0, 0.1]"))
    assert "0.1]" in map_yaml_text(
        "m.pgm",
        mode="trinary",
        resolution=0.05,
        origin=loaded.origin,
        free_thresh=0.25,
        occupied_thresh=0.65,
    )


def test_awkward_image_names_are_quoted(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.zeros((1, 1), np.int8), 0.1)
    for name in ("#hash", "a: b", "- dash", "true", "my map"):
        yaml_path, _ = save_map(grid, tmp_path / f"{name}.yaml")
        assert read_map(yaml_path).image_path == tmp_path / f"{name}.pgm"


def test_png_and_bmp_trinary_round_trip(tmp_path: Path) -> None:
    data = np.array([[0, 100], [-1, 0]], np.int8)
    grid = OccupancyGrid(data, 0.05, Pose2D(1.0, 2.0, -0.5))
    for fmt in ("png", "PNG", "bmp"):
        yaml_path, image = save_map(grid, tmp_path / f"m_{fmt}.yaml", image_format=fmt)
        assert image.suffix == f".{fmt.lower()}"
        assert load_map(yaml_path) == grid


def test_scale_into_pgm_warns_about_unknown_cells(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.array([[0, -1]], np.int8), 0.1)
    with pytest.warns(UserWarning, match="transparency"):
        yaml_path, _ = save_map(
            grid,
            tmp_path / "m.yaml",
            mode="scale",
            image_format="pgm",
            free_thresh=0.0,
            occupied_thresh=1.0,
        )
    np.testing.assert_array_equal(load_map(yaml_path).data, [[0, 50]])


@pytest.mark.parametrize(
    ("kwargs", "key", "words"),
    [
        ({"mode": "scal"}, "mode", "unknown map mode"),
        ({"occupied_thresh": 1.5}, "occupied_thresh", "1.0 or less"),
        ({"free_thresh": -0.5}, "free_thresh", "0.0 or greater"),
        ({"free_thresh": 0.7, "occupied_thresh": 0.2}, "free_thresh", "smaller"),
        ({"free_thresh": float("nan")}, "free_thresh", "finite"),
        ({"image_format": "jpg"}, "image_format", "unsupported image format"),
    ],
)
def test_save_refuses_what_map_saver_refuses(
    tmp_path: Path, kwargs: dict, key: str, words: str
) -> None:
    grid = OccupancyGrid(np.zeros((2, 2), np.int8), 0.1)
    with pytest.raises(MapError, match=words) as info:
        save_map(grid, tmp_path / "m.yaml", **kwargs)
    assert info.value.key == key
    assert not list(tmp_path.iterdir())  # nothing half-written


def test_save_refuses_empty_or_non_finite_maps(tmp_path: Path) -> None:
    with pytest.raises(MapError, match="empty"):
        save_map(OccupancyGrid(np.zeros((0, 3), np.int8), 0.1), tmp_path / "e.yaml")
    with pytest.raises(MapError, match="finite"):
        save_map(
            OccupancyGrid(np.zeros((1, 1), np.int8), 0.1, Pose2D(math.inf, 0, 0)),
            tmp_path / "i.yaml",
        )


# --- property: save-then-load is exact ---------------------------------------------------------

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(
    data=hnp.arrays(
        np.int8,
        hnp.array_shapes(min_dims=2, max_dims=2, min_side=1, max_side=24),
        elements=st.sampled_from([-1, 0, 100]),
    ),
    resolution=st.floats(min_value=1e-4, max_value=100.0, allow_nan=False),
    x=finite,
    y=finite,
    yaw=st.floats(min_value=-math.pi, max_value=math.pi),
    fmt=st.sampled_from(["pgm", "png"]),
)
def test_random_trinary_grids_round_trip(
    tmp_path_factory: pytest.TempPathFactory,
    data: np.ndarray,
    resolution: float,
    x: float,
    y: float,
    yaw: float,
    fmt: str,
) -> None:
    grid = OccupancyGrid(data, resolution, Pose2D(x, y, yaw))
    folder = tmp_path_factory.mktemp("rt")
    yaml_path, _ = save_map(grid, folder / "m.yaml", image_format=fmt)
    assert load_map(yaml_path) == grid


@settings(max_examples=30, deadline=None)
@given(
    data=hnp.arrays(
        np.int8,
        hnp.array_shapes(min_dims=2, max_dims=2, min_side=1, max_side=16),
        elements=st.integers(-1, 100),
    ),
    mode=st.sampled_from(["scale", "raw"]),
)
def test_random_scale_and_raw_grids_round_trip(
    tmp_path_factory: pytest.TempPathFactory, data: np.ndarray, mode: str
) -> None:
    grid = OccupancyGrid(data, 0.05, Pose2D(-1.0, 2.0, 0.0))
    folder = tmp_path_factory.mktemp("rt")
    yaml_path, _ = save_map(
        grid, folder / "m.yaml", mode=mode, free_thresh=0.0, occupied_thresh=1.0
    )
    assert load_map(yaml_path) == grid


def test_every_scale_value_round_trips(tmp_path: Path) -> None:
    data = np.arange(-1, 101, dtype=np.int8).reshape(6, 17)
    grid = OccupancyGrid(data, 0.05)
    yaml_path, _ = save_map(
        grid, tmp_path / "m.yaml", mode="scale", free_thresh=0.0, occupied_thresh=1.0
    )
    assert load_map(yaml_path) == grid
