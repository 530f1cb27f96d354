"""The files btnav ships stay in step with what they are made from."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from btnav.core.resources import BUNDLED_KINDS
from btnav.maps import load_map
from btnav.mission import Mission, MissionError
from btnav.sim.rasterize import rasterize
from btnav.sim.world import World

REPO = Path(__file__).resolve().parents[1]


def test_small_office_map_is_the_rasterised_world():
    shipped = load_map(REPO / "maps" / "small_office.yaml")
    fresh = rasterize(World.from_file(REPO / "worlds" / "small_office.yaml"), resolution=0.05)
    assert shipped.resolution == fresh.resolution
    assert np.allclose(shipped.origin.as_array(), fresh.origin.as_array())
    assert np.array_equal(shipped.data, fresh.data), (
        "maps/small_office.* is stale: btnav map from-world worlds/small_office.yaml "
        "-o maps/small_office.yaml"
    )


def test_params_nav2_params_is_nav2s_file_byte_for_byte(nav2_params_file):
    assert (REPO / "params" / "nav2_params.yaml").read_bytes() == nav2_params_file.read_bytes()


def test_an_installed_btnav_carries_the_bundled_folders(tmp_path):
    """The wheel pip builds holds trees, worlds, maps, params and missions in btnav/data,
    where `bundled_dir` looks in an installed btnav. Built as a user's `pip install .`
    builds it (an isolated build: a venv of CPython 3.12+ has no setuptools of its own)."""
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(tmp_path), "."],
        cwd=REPO,
        check=True,
        capture_output=True,
    )
    (wheel,) = tmp_path.glob("btnav-*.whl")
    with zipfile.ZipFile(wheel) as packed:
        for kind in BUNDLED_KINDS:
            for file in (REPO / kind).rglob("*"):
                if file.is_file() and "__pycache__" not in file.parts:
                    inside = f"btnav/data/{kind}/{file.relative_to(REPO / kind).as_posix()}"
                    assert packed.read(inside) == file.read_bytes()
        page = REPO / "src" / "btnav" / "viz" / "live" / "static"  # the live view's page
        for file in page.iterdir():
            assert packed.read(f"btnav/viz/live/static/{file.name}") == file.read_bytes()


def test_a_bundled_mission_is_found_by_its_bare_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # nothing called office_tour here
    assert Mission.load("office_tour").file == REPO / "missions" / "office_tour.yaml"
    with pytest.raises(MissionError) as info:
        Mission.load("office_tur")
    assert info.value.suggestion == "office_tour"
