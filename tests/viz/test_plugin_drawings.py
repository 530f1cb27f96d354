"""A user's controller draws itself: its `local_plan` and `drawables` show in run.gif's
frames and on run.png, with no attribute btnav knows of."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.controller import MPPIController
from btnav.core.drawing import polygon
from btnav.mission import Mission, run_mission
from btnav.plugins import register, unregister

from ..mission.missions import write_mission
from .test_run_gif import color_pixels, gif_frames

BOX_COLOR = "#ff00ff"


@pytest.fixture
def boxed_controller():
    """MPPI under a user's name, with a local plan of its own (1 m straight ahead) and a
    square drawn round the robot in base_footprint."""

    @register("controller", "my_pkg::BoxedMPPI")
    class Boxed(MPPIController):
        def local_plan(self, pose):
            ahead = np.linspace(0.0, 1.0, 11)
            return np.stack(
                [pose.x + ahead * np.cos(pose.yaw), pose.y + ahead * np.sin(pose.yaw), ahead * 0],
                axis=-1,
            )

        def drawables(self):
            square = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            return [polygon(square, "base_footprint", BOX_COLOR, "my box")]

    yield
    unregister("controller", "my_pkg::BoxedMPPI")


def test_a_users_controller_shows_its_local_plan_and_its_box(tmp_path, boxed_controller, gif_probe):
    path = write_mission(
        tmp_path,
        "boxed",
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
        time_limit=4,
        outputs=["report", "gif_probe", "png"],
    )
    mission = Mission.load(
        path, overrides={"controller_server.FollowPath.plugin": "my_pkg::BoxedMPPI"}
    )
    run_mission(mission, tmp_path / "out")
    (gif,) = gif_probe
    moving = [s for s in gif.recorder.snapshots if len(s.local_plan)]
    assert moving
    for snap in moving[1:]:  # the controller's own line: 1 m long, from the robot
        length = np.hypot(*(snap.local_plan[-1] - snap.local_plan[0]))
        assert length == pytest.approx(1.0, abs=0.05)
    box = moving[-1].drawings[0]
    assert box.label == "my box" and box.frame == "map"
    x, y, _ = moving[-1].robot
    assert np.allclose(box.points.mean(axis=0), (x, y), atol=0.05)  # round the robot
    frames, _, _ = gif_frames(tmp_path / "out" / "run.gif")
    assert color_pixels(frames[len(frames) // 2], BOX_COLOR) > 40
    from PIL import Image

    png = np.asarray(Image.open(tmp_path / "out" / "run.png").convert("RGB"))
    assert color_pixels(png, BOX_COLOR) > 40
