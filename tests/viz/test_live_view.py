"""`btnav run --view` without a browser: the view changes nothing in the run, and its
commands (sent as the page sends them) steer it at the next update."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("aiohttp", reason="the live view needs aiohttp (the view extra)")

from btnav.mission import Mission, run_mission
from btnav.viz.live.live_view import LiveView

from ..mission.missions import write_mission


def short_mission(folder, name="live"):
    return write_mission(
        folder,
        name,
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
        time_limit=5,
        outputs=["trajectory"],
    )


def test_a_view_with_no_page_gives_the_same_trajectory_bytes(tmp_path):
    path = short_mission(tmp_path)
    run_mission(Mission.load(path), tmp_path / "plain")
    view = LiveView(speed=0).start()
    try:
        mission = Mission.load(path)
        run_mission(mission, tmp_path / "viewed", attach=lambda nav: view.attach(nav, mission))
    finally:
        view.close()
    plain = (tmp_path / "plain" / "trajectory.csv").read_bytes()
    assert len(plain) > 1000
    assert (tmp_path / "viewed" / "trajectory.csv").read_bytes() == plain


def test_the_messages_a_page_gets_are_json_with_the_run_in_them(tmp_path):
    path = short_mission(tmp_path)
    view = LiveView(speed=0)
    sent = []
    view.hub.publish = sent.append  # no server: keep what would be sent
    view.hub.clients = {object()}  # one page
    mission = Mission.load(path)
    view.commands.put({"cmd": "hello"})
    view.commands.put({"cmd": "costmap", "which": "global"})
    run_mission(mission, None, attach=lambda nav: view.attach(nav, mission))
    kinds = {m["type"] for m in sent}
    assert {"static", "map", "costmap", "tree", "frame"} <= kinds
    frames = [m for m in sent if m["type"] == "frame"]
    assert frames[-1]["t"] > frames[0]["t"]
    assert frames[-1]["robot"][0] > frames[0]["robot"][0] + 0.5  # it drove towards x = 3
    assert any(len(f["scan"]) > 100 and len(f["local_plan"]) for f in frames)
    assert any("R" in f["bt"] for f in frames)  # Groot's running
    json.dumps(sent)  # all JSON


def test_the_recording_keeps_the_run_for_the_replay(tmp_path):
    from btnav.viz.live.replay import Replay

    path = write_mission(
        tmp_path,
        "rec",
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
        time_limit=5,
        outputs=["trajectory", "recording"],
    )
    run_mission(Mission.load(path), tmp_path / "out")
    plain = tmp_path / "plain"
    run_mission(Mission.load(path, overrides={"mission.outputs": ["trajectory"]}), plain)
    trajectory = (tmp_path / "out" / "trajectory.csv").read_bytes()
    assert trajectory == (plain / "trajectory.csv").read_bytes()  # recording changed nothing
    replay = Replay(tmp_path / "out")
    times = [f["t"] for f in replay.frames]
    assert times[0] == 0.0 and times[-1] == pytest.approx(5.0, abs=0.3)
    assert len(times) >= 5 * 5  # 5 Hz
    assert replay.frames[-1]["result"] is not None
    sent = []
    replay.hub.publish = sent.append
    replay.command({"cmd": "hello"})
    assert [m["type"] for m in sent][:2] == ["static", "replay"]
    assert {"map", "frame"} <= {m["type"] for m in sent}
    sent.clear()
    replay.command({"cmd": "seek", "index": len(times) - 1})
    assert "tree" in {m["type"] for m in sent}  # the tree that ran by then
    assert sent[-1]["t"] == times[-1]
    sent.clear()
    replay.command({"cmd": "seek", "index": len(times) - 2})
    assert [m["type"] for m in sent] == ["frame"]  # the page has the rest
