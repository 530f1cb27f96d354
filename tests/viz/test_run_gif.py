"""`outputs: [gif]` and `btnav run --gif`: the run as an animation, without changing the run."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageSequence

from btnav.cli import main
from btnav.core.errors import BtnavError
from btnav.mission import Mission, run_mission
from btnav.viz.run_gif import PARTICLE_COLOR, RunGif

from ..mission.missions import REPO, write_mission

#: The small office's bounds (12 m x 8 m) with the 2 % margin, at RunGif.size_px wide.
OFFICE_SIZE = (720, round(720 * 8.48 / 12.48) + 26)


def amcl_mission(folder: Path, outputs: list[str], name: str = "gif") -> Path:
    """A short drive from (1, 1) towards (3, 2) with AMCL, cut by its time limit."""
    return write_mission(
        folder,
        name,
        localization="amcl",
        initial_pose=[1.0, 1.0, 0.0],
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
        time_limit=6,
        outputs=outputs,
    )


def expected_frames(sim_time: float, rate: float, cap: int) -> int:
    """One frame per 1/rate s from the start, thinned by halving to fit cap - 1, then the end."""
    ticks = math.floor(sim_time * rate + 1e-9)
    stride = 1
    while ticks // stride + 1 > cap - 1:
        stride *= 2
    last = (ticks // stride) * stride / rate
    return ticks // stride + 1 + (1 if sim_time > last + 1e-9 else 0)


def gif_frames(path: Path) -> tuple[list[np.ndarray], list[int], tuple[int, int]]:
    with Image.open(path) as im:
        size = im.size
        frames = [
            (np.asarray(f.convert("RGB")), f.info["duration"]) for f in ImageSequence.Iterator(im)
        ]
    return [f for f, _ in frames], [d for _, d in frames], size


def color_pixels(frame: np.ndarray, color: str) -> int:
    rgb = np.array([int(color[i : i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(frame.astype(int) - rgb).sum(axis=2) < 30).sum())


def test_the_gif_shows_the_run_and_changes_nothing_in_it(tmp_path):
    plain = ["report", "trajectory", "bt_log"]
    report = run_mission(Mission.load(amcl_mission(tmp_path, plain)), tmp_path / "plain")
    path = amcl_mission(tmp_path, [*plain, "gif"])
    with_gif = run_mission(Mission.load(path), tmp_path / "gif")
    assert with_gif.outputs == [*report.outputs, "run.gif"]

    # Reading only: the same run, bit for bit (but for the wall time and the file list).
    a, b = (json.loads((tmp_path / d / "report.json").read_text()) for d in ("plain", "gif"))
    for r in (a, b):
        del r["wall_time"], r["outputs"]
    assert a == b
    for name in ("trajectory.csv", "bt_log.jsonl"):
        assert (tmp_path / "plain" / name).read_bytes() == (tmp_path / "gif" / name).read_bytes()

    gif = tmp_path / "gif" / "run.gif"
    frames, durations, size = gif_frames(gif)
    assert size == OFFICE_SIZE
    assert len(frames) == expected_frames(report.sim_time, RunGif.frame_rate, RunGif.max_frames)
    assert durations == [RunGif.frame_ms] * (len(frames) - 1) + [RunGif.end_ms]
    assert gif.stat().st_size < 400_000
    # AMCL's particle cloud (spread by the odometry noise as the robot drives) is drawn.
    assert color_pixels(frames[-1], PARTICLE_COLOR) > 50
    assert not np.array_equal(frames[1], frames[-2])


def test_btnav_run_gif_writes_it_thinned_to_the_frame_cap(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(RunGif, "max_frames", 9)
    path = amcl_mission(tmp_path, ["report"])
    out = tmp_path / "out"
    main(["run", str(path), "--out", str(out), "--gif", "--set", "mission.time_limit=5"])
    assert "run.gif" in capsys.readouterr().out
    report = json.loads((out / "report.json").read_text())
    assert report["outputs"] == ["report.json", "run.gif"]
    frames, durations, _size = gif_frames(out / "run.gif")
    # 5 s at 4 Hz is 21 frames; thinned evenly (one in 4) to fit 9 with the closing frame.
    assert len(frames) == expected_frames(report["sim_time"], RunGif.frame_rate, 9) <= 9
    assert len(durations) == len(frames)


def test_amcl_frames_keep_a_thinned_particle_cloud(tmp_path, gif_probe):
    path = amcl_mission(tmp_path, ["report", "gif_probe"])
    report = run_mission(Mission.load(path), tmp_path / "out")
    (gif,) = gif_probe
    snaps = gif.recorder.snapshots
    times = np.array([s.time for s in snaps])
    np.testing.assert_allclose(np.diff(times), 1.0 / RunGif.frame_rate, atol=1e-6)
    assert times[-1] <= report.sim_time
    for snap in snaps:
        assert snap.particles is not None and 0 < len(snap.particles) <= 600
        assert snap.slam_map is None
    # Each frame keeps the cloud as it was then: it starts on the initial pose and spreads.
    spread = [float(np.ptp(s.particles, axis=0).max()) for s in (snaps[0], snaps[-1])]
    assert spread[0] < 0.05 < 0.3 < spread[1]
    assert snaps[-1].robot[0] > snaps[0].robot[0] + 0.5
    assert any(len(s.local_plan) and len(s.plan) for s in snaps)  # MPPI's plan and the path
    assert any("FollowPath" in s.actions for s in snaps)
    assert len(snaps[0].scan) > 100


@pytest.mark.slow
def test_slam_frames_show_the_map_growing(tmp_path, gif_probe):
    mission = Mission.load(
        REPO / "missions" / "corridor_loop_slam.yaml",
        overrides={"mission.time_limit": 12, "mission.outputs": ["report", "gif_probe"]},
    )
    run_mission(mission, tmp_path / "out")
    (gif,) = gif_probe
    maps = [s.slam_map for s in gif.recorder.snapshots if s.slam_map is not None]
    assert maps and maps[-1].known_cells > 2 * maps[0].known_cells
    assert all(s.particles is None for s in gif.recorder.snapshots)
    frames, _durations, _size = gif_frames(tmp_path / "out" / "run.gif")
    assert (np.abs(frames[-1].astype(int) - frames[0].astype(int)).sum(axis=2) > 60).sum() > 2000


def test_without_pillow_the_gif_is_a_clear_error_before_the_run(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "PIL", None)  # `from PIL import ...` now fails
    path = amcl_mission(tmp_path, ["report", "gif"])
    with pytest.raises(BtnavError, match=r"btnav\[viz\]"):
        run_mission(Mission.load(path), tmp_path / "out")
    assert not (tmp_path / "out" / "report.json").exists()
