"""`btnav map show`: a map as a picture, beside it by default."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from btnav.cli import main

REPO = Path(__file__).resolve().parents[2]


def test_map_show_draws_the_map_beside_it(tmp_path, capsys):
    (tmp_path / "office.yaml").write_text(
        (REPO / "maps" / "small_office.yaml")
        .read_text()
        .replace("small_office.pgm", str(REPO / "maps" / "small_office.pgm"))
    )
    assert main(["map", "show", str(tmp_path / "office.yaml")]) == 0
    assert f"wrote {tmp_path / 'office.png'}" in capsys.readouterr().out
    picture = np.asarray(Image.open(tmp_path / "office.png").convert("L"))
    assert picture.shape[1] > picture.shape[0]  # 12 x 8 m: wider than tall
    assert (picture < 40).mean() > 0.01 and (picture > 240).mean() > 0.3  # walls and free space


def test_map_show_of_a_missing_map_is_one_error(tmp_path, capsys):
    assert main(["map", "show", str(tmp_path / "none.yaml")]) == 2
    assert "file not found" in capsys.readouterr().err
