"""`btnav run --view` without a browser: the view changes nothing in the run, and its
commands (sent as the page sends them) steer it at the next update."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("aiohttp", reason="the live view needs aiohttp (the view extra)")

from btnav.mission import Mission, run_mission  # noqa: E402
from btnav.viz.live.live_view import LiveView  # noqa: E402

from ..mission.missions import write_mission  # noqa: E402


def short_mission(folder, name="live"):
    return write_mission(
        folder, name, task={"navigate_to_pose": [3.0, 2.0, 1.57]}, time_limit=5, outputs=["trajectory"]
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
