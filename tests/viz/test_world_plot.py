"""`btnav world show` draws a picture a user can read: walls, obstacles, the robot, a scan."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from btnav.cli import main as cli_main
from btnav.cli.world import show_world_main
from btnav.core.errors import BtnavError
from btnav.sim import lidar as _lidar  # noqa: F401  (registers the lidar plugin)
from btnav.sim.world import World
from btnav.sim.world_sensors import make_sensors
from btnav.sim.world_spec import WorldSpec
from btnav.viz.world_plot import MOVING_COLOR, ROBOT_COLOR, SCAN_COLOR, draw_world

Image = pytest.importorskip("PIL.Image")

REPO = Path(__file__).resolve().parents[2]
SMALL_OFFICE = REPO / "worlds" / "small_office.yaml"


def _rgb(hex_color: str) -> np.ndarray:
    return np.array([int(hex_color[i : i + 2], 16) for i in (1, 3, 5)])


def _pixels_near(img: np.ndarray, hex_color: str, tol: int = 40) -> int:
    return int((np.abs(img[..., :3].astype(int) - _rgb(hex_color)).max(axis=-1) <= tol).sum())


def test_world_show_writes_a_readable_png(tmp_path, capsys):
    out = tmp_path / "world.png"
    assert show_world_main(SMALL_OFFICE, out) == 0
    assert "wrote" in capsys.readouterr().out
    img = np.asarray(Image.open(out))
    assert img.shape[0] > 400 and img.shape[1] > 600
    assert len(np.unique(img.reshape(-1, img.shape[-1]), axis=0)) > 50  # not a blank canvas
    assert _pixels_near(img, "#4a4a4a", 10) > 5000  # walls and obstacles
    assert _pixels_near(img, MOVING_COLOR, 10) > 200  # the moving obstacle and its route
    assert _pixels_near(img, SCAN_COLOR, 30) > 300  # the scan's returns
    assert _pixels_near(img, ROBOT_COLOR, 60) + _pixels_near(img, "#8da6d6", 40) > 200  # robot


def test_cli_world_show(tmp_path):
    out = tmp_path / "w.png"
    assert cli_main(["world", "show", str(SMALL_OFFICE), "-o", str(out)]) == 0
    assert out.stat().st_size > 10_000


def test_cli_world_show_bad_world_is_a_user_error(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("bounds: [[0, 0], [5, 5]]\nrobot: {pose: [1, 1, 0]}\nwals: []\n")
    assert cli_main(["world", "show", str(bad), "-o", str(tmp_path / "x.png")]) == 2
    assert "walls" in capsys.readouterr().err  # did you mean 'walls'?


def test_unwritable_output_is_a_btnav_error(tmp_path):
    (tmp_path / "a_file").write_text("not a folder")
    with pytest.raises(BtnavError, match="cannot create the folder"):
        show_world_main(SMALL_OFFICE, tmp_path / "a_file" / "w.png")


def test_output_folder_is_created(tmp_path):
    show_world_main(SMALL_OFFICE, tmp_path / "new" / "dir" / "w.png")
    assert (tmp_path / "new" / "dir" / "w.png").is_file()


def test_draw_world_on_given_axes_with_polygon_robot_and_stopping_obstacle(tmp_path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    spec = WorldSpec.from_text(
        """
world: tiny
bounds: [[0, 0], [6, 4]]
walls: [[[0, 0], [6, 0], [6, 4], [0, 4], [0, 0]]]
obstacles:
  - polygon: {points: [[3, 1], [4, 1], [3.5, 2]],
              moves: {path: [[3, 2.5]], speed: 0.5, loop: false}}
robot:
  footprint: {polygon: [[0.3, 0.2], [-0.3, 0.2], [-0.3, -0.2], [0.3, -0.2]]}
  pose: [1.0, 1.0, 0.5]
  sensors:
    - lidar: {frame: base_scan, pose: [0.2, 0.0, 0.0], beams: 90, range: [0.1, 5.0]}
"""
    )
    world = World(spec)
    world.step(1.0)  # the obstacle has moved half a metre
    scan = make_sensors(world, seed=0)[0].measure(world.time)
    fig = Figure()
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    assert draw_world(world, scan, ax) is ax
    labels = [text.get_text() for text in ax.get_legend().get_texts()]  # what the user sees
    assert {"walls and obstacles", "moving obstacle", "route", "robot"} <= set(labels)
    assert any(label.startswith("scan (") for label in labels)
    fig.savefig(tmp_path / "tiny.png")
    assert (tmp_path / "tiny.png").stat().st_size > 5_000


def test_missing_matplotlib_says_how_to_install_it(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # `import matplotlib` now fails
    with pytest.raises(BtnavError, match=r"btnav\[viz\]"):
        show_world_main(SMALL_OFFICE, tmp_path / "w.png")
