"""`outputs: [png]` draws the run: the world, the costmap, the plan, the path, the contacts."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from btnav.mission import Mission, RunOutput, run_mission
from btnav.plugins import register, unregister
from btnav.viz.run_plot import draw_run

from ..mission.missions import write_mission
from ..mission.test_outputs import contact_mission, walker_line


def test_png_output_draws_the_run(tmp_path):
    path = write_mission(
        tmp_path,
        "pic",
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
        outputs=["report", "png"],
        time_limit=4,
    )
    report = run_mission(Mission.load(path), tmp_path / "out")
    assert report.outputs == ["report.json", "run.png"]
    image = np.asarray(Image.open(tmp_path / "out" / "run.png").convert("RGB")).astype(int)
    assert image.shape[0] > 300 and image.shape[1] > 400
    path_blue = (np.abs(image - [0x1F, 0x5F, 0xBF]).sum(axis=2) < 40).sum()
    assert path_blue > 100  # the path taken is drawn


@pytest.fixture
def captured():
    """The RunOutput the `png` plugin gets, kept to draw again and look at the figure."""
    runs: list[RunOutput] = []

    @register("output", "capture_run")
    class Capture:
        files = ()

        def write(self, run: RunOutput) -> None:
            runs.append(run)

    yield runs
    unregister("output", "capture_run")


def test_run_png_shows_the_contact_the_plan_the_costmap_and_the_estimate(tmp_path, captured):
    path = contact_mission(tmp_path, outputs=["report", "capture_run", "png"])
    report = run_mission(Mission.load(path), tmp_path / "out")
    assert (tmp_path / "out" / "run.png").is_file()
    (run,) = captured
    ax = draw_run(run).axes[0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    for entry in (
        "path (ground truth)",
        "estimate (localisation)",
        "global plan (last)",
        "global costmap (inflated)",
        "contact (1)",
    ):
        assert entry in legend
    lines = {line.get_label(): line for line in ax.get_lines()}

    # The estimate is told apart from ground truth by colour and line style.
    truth, estimate = lines["path (ground truth)"], lines["estimate (localisation)"]
    assert truth.get_color() != estimate.get_color()
    assert truth.get_linestyle() == "-" and estimate.get_linestyle() != "-"

    # The plan is the last one the controller followed: it ends at the goal.
    plan = lines["global plan (last)"].get_xydata()
    assert len(plan) > 10 and np.hypot(*(plan[-1] - [3.0, 2.0])) < 0.1

    # The contact: a red X where the robot was, and text naming the obstacle and its line.
    [contact] = report.contacts
    x_mark = lines["contact (1)"]
    assert x_mark.get_marker() == "x" and x_mark.get_color() == "#d62728"
    assert x_mark.get_xydata().tolist() == [contact["pose"][:2]]
    texts = [t.get_text() for t in ax.texts]
    assert any(f"obstacles[9] (circle), line {walker_line(tmp_path)}" in t for t in texts)

    # The inflated global costmap lies under the walls and obstacles, see-through.
    [costmap] = ax.get_images()
    solids = [c for c in ax.collections if c.get_label() == "walls and obstacles"]
    assert 0 < costmap.get_alpha() < 1 and costmap.get_zorder() < solids[0].get_zorder()
    costs = costmap.get_array()
    assert costs.max() >= 253 and costs.count() > 0  # lethal and inscribed cells shown
    assert np.ma.getmaskarray(costs).any()  # free space left clear
