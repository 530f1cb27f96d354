"""`outputs: [png]` draws the run: the world, the path taken and the goals."""

from __future__ import annotations

import numpy as np
from PIL import Image

from btnav.mission import Mission, run_mission

from ..mission.missions import write_mission


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
