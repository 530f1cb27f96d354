"""`--foxglove`: a real Foxglove WebSocket client sees the run live and steers it.

The client speaks the Foxglove WebSocket protocol (foxglove-sdk's servers name it
`foxglove.sdk.v1`, the successor of `foxglove.websocket.v1`): JSON control messages
(serverInfo, advertise, subscribe by channel id) and binary message frames (opcode 1,
u32 subscription id, u64 log time, payload); a client publishes by advertising a
channel and sending (opcode 1, u32 client channel id, payload).
"""

from __future__ import annotations

import asyncio
import json
import math
import os
import struct
import subprocess
import sys
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("foxglove")
pytest.importorskip("rosbags")
websockets = pytest.importorskip("websockets")

from btnav.cli import main as cli_main  # noqa: E402
from btnav.core.errors import BtnavError  # noqa: E402
from btnav.mission import Mission, run_mission  # noqa: E402
from btnav.viz import ros_messages as rm  # noqa: E402
from btnav.viz.foxglove_live import FoxgloveLive, FoxgloveOutput, LiveSettings  # noqa: E402

from ..mission.missions import TOLERANCE, TOUR  # noqa: E402

SUBPROTOCOLS = ["foxglove.sdk.v1", "foxglove.websocket.v1"]
FAST = LiveSettings(port=0, speed=0)  # a free port; as fast as it goes
GOAL = (2.2, 1.3, 0.5)  # a short drive from the tour's start (1, 1)


class Client:
    """A Foxglove WebSocket client on its own thread and event loop (the test's sim runs
    on the main thread, as `btnav run` runs it)."""

    def __init__(self, port: int, script: Callable[[Any, Client], Any]) -> None:
        self.port = port
        self.script = script
        self.info: dict[str, Any] = {}
        self.channels: dict[str, dict[str, Any]] = {}  # topic -> the server's advertisement
        self.received: dict[str, list[bytes]] = {}
        self.done = threading.Event()
        self.error: BaseException | None = None
        self._thread = threading.Thread(target=lambda: asyncio.run(self._main()), daemon=True)
        self._thread.start()

    async def _main(self) -> None:
        try:
            url = f"ws://127.0.0.1:{self.port}"
            async with websockets.connect(url, subprotocols=SUBPROTOCOLS) as ws:
                self.ws = ws
                await self.script(ws, self)
        except BaseException as err:  # reported on the main thread
            self.error = err
        finally:
            self.done.set()

    async def receive(self, until: Callable[[], bool], subscriptions: dict[int, str]) -> None:
        """Read frames (advertisements, messages) until `until()` is true."""
        while not until():
            frame = await asyncio.wait_for(self.ws.recv(), 30)
            if isinstance(frame, str):
                msg = json.loads(frame)
                if msg["op"] == "serverInfo":
                    self.info = msg
                elif msg["op"] == "advertise":
                    for ch in msg["channels"]:
                        self.channels[ch["topic"]] = ch
                continue
            opcode, sub = frame[0], struct.unpack_from("<I", frame, 1)[0]
            if opcode == 1 and sub in subscriptions:
                self.received.setdefault(subscriptions[sub], []).append(bytes(frame[13:]))

    async def subscribe(self, topics: list[str]) -> dict[int, str]:
        await self.receive(lambda: all(t in self.channels for t in topics), {})
        subs = {i + 1: t for i, t in enumerate(topics)}
        request = [{"id": i, "channelId": self.channels[t]["id"]} for i, t in subs.items()]
        await self.ws.send(json.dumps({"op": "subscribe", "subscriptions": request}))
        return subs

    def check(self) -> None:
        if self.error is not None:
            raise self.error


def tour(**overrides: Any) -> Mission:
    sets = {"mission.task": {"navigate_to_pose": [2.2, 1.3, 0.0]}, "mission.time_limit": 20}
    return Mission.load(TOUR, overrides={**sets, **overrides})


def serve_until(live: FoxgloveLive, client: Client, sim_limit: float = 120.0) -> None:
    """Run the sim (as `btnav run` does after the task) until the client is done."""
    end = live.runtime.now + sim_limit
    live.idle(until=lambda: client.done.is_set() or live.runtime.now > end)
    client.check()


def test_a_client_gets_the_scan_and_the_latched_map(tmp_path):
    mission = tour()
    nav = mission.navigator()
    live = FoxgloveLive(nav, FAST)
    grid = nav.stack.map_server.map
    scan = nav.runtime.latest_scan

    async def script(ws: Any, c: Client) -> None:
        subs = await c.subscribe(["/scan", "/map"])
        await c.receive(
            lambda: len(c.received.get("/scan", [])) >= 3 and "/map" in c.received, subs
        )

    try:
        client = Client(live.port, script)
        serve_until(live, client)
    finally:
        live.close()
    assert "clientPublish" in client.info["capabilities"]
    channel = client.channels["/scan"]
    assert (channel["schemaName"], channel["schemaEncoding"], channel["encoding"]) == (
        rm.SCAN,
        "ros2msg",
        "cdr",
    )
    assert "float32[] ranges" in channel["schema"]
    msgs = rm.RosMessages()
    decoded = [msgs.deserialize(raw, rm.SCAN) for raw in client.received["/scan"]]
    assert all(len(s.ranges) == len(scan.ranges) for s in decoded)
    assert all(s.header.frame_id == scan.frame_id for s in decoded)
    stamps = [s.header.stamp.sec + s.header.stamp.nanosec * 1e-9 for s in decoded]
    assert stamps == sorted(stamps) and len(set(stamps)) == len(stamps)  # live: new scans
    assert np.all(np.isfinite(decoded[-1].ranges) | np.isinf(decoded[-1].ranges))
    # The map was sent at the start, before the client came: it gets it all the same.
    (raw,) = client.received["/map"][:1]
    shown = msgs.deserialize(raw, rm.OCCUPANCY_GRID)
    assert (shown.info.width, shown.info.height) == (grid.width, grid.height)
    assert np.array_equal(shown.data, np.asarray(grid.data, dtype=np.int8).ravel())


def _pose_stamped(msgs: rm.RosMessages, x: float, y: float, yaw: float) -> bytes:
    from btnav.core.geometry import Pose2D

    t = msgs.store.types
    msg = t[rm.POSE_STAMPED](header=msgs.header(0.0, "map"), pose=msgs.pose(Pose2D(x, y, yaw)))
    return msgs.serialize(msg, rm.POSE_STAMPED)


def test_a_goal_pose_a_client_publishes_is_a_goal_the_robot_reaches():
    nav = tour().navigator()  # no task sent: the client's goal is the only one
    live = FoxgloveLive(nav, FAST)
    payload = _pose_stamped(rm.RosMessages(), *GOAL)
    reached = threading.Event()

    async def script(ws: Any, c: Client) -> None:
        await c.receive(lambda: bool(c.info), {})
        assert "clientPublish" in c.info["capabilities"]
        channel = {"id": 7, "topic": "/goal_pose", "encoding": "cdr"}
        channel["schemaName"] = rm.POSE_STAMPED
        await ws.send(json.dumps({"op": "advertise", "channels": [channel]}))
        await asyncio.sleep(0.2)  # the advertisement is handled before the message
        await ws.send(b"\x01" + struct.pack("<I", 7) + payload)
        await asyncio.to_thread(reached.wait, 60)

    def done() -> bool:
        handle = nav.handle
        if handle is not None and handle.done:
            reached.set()
        return reached.is_set()

    try:
        client = Client(live.port, script)
        end = nav.now + 120.0
        live.idle(until=lambda: done() or client.done.is_set() or nav.now > end)
        client.check()
    finally:
        live.close()
    assert nav.handle is not None and nav.get_result() is not None
    assert nav.get_result().succeeded
    gt = nav.world.robot_pose
    assert math.hypot(gt.x - GOAL[0], gt.y - GOAL[1]) < TOLERANCE


def test_a_served_run_with_no_client_is_the_same_run(tmp_path):
    outputs = ["report", "trajectory", "bt_log"]
    served = FoxgloveOutput(FAST)
    with_server = run_mission(
        tour(**{"mission.outputs": outputs}), tmp_path / "with", plugins={"foxglove": served}
    )
    without = run_mission(tour(**{"mission.outputs": outputs}), tmp_path / "without")
    assert served.live is not None and served.live.server is None  # stopped at the end
    assert with_server.status == without.status == "succeeded"
    for name in ("trajectory.csv", "bt_log.jsonl"):
        assert (tmp_path / "with" / name).read_bytes() == (tmp_path / "without" / name).read_bytes()


def test_without_foxglove_the_cli_says_which_extra(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "foxglove", None)
    code = cli_main(["run", str(TOUR), "-o", str(tmp_path), "--foxglove"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and 'pip install "btnav[view]"' in err[0]
    assert not (tmp_path / "report.json").exists()
    with pytest.raises(BtnavError, match="view"):
        FoxgloveOutput()


def test_a_plain_run_imports_no_foxglove(tmp_path):
    """No foxglove-sdk, so no server and no thread: the viewer costs a plain run nothing."""
    code = (
        "import sys\n"
        "from btnav.cli import main\n"
        f"main(['run', {str(TOUR)!r}, '-o', {str(tmp_path)!r}, '--set', 'mission.time_limit=1'])\n"
        "assert not [m for m in sys.modules if m.split('.')[0] == 'foxglove'], 'imported'\n"
    )
    env = {"PYTHONPATH": str(Path(__file__).resolve().parents[2] / "src")}
    done = subprocess.run(
        [sys.executable, "-c", code], env={**os.environ, **env}, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "report.json").is_file()


def test_an_initial_pose_a_client_publishes_resets_amcl():
    nav = tour().navigator()
    live = FoxgloveLive(nav, FAST)
    msgs = rm.RosMessages()
    from btnav.core.geometry import Pose2D
    from btnav.core.messages import PoseWithCovariance

    there = Pose2D(1.5, 1.2, 0.3)
    cov = np.diag([0.01, 0.01, 0.0025])
    msg = msgs.pose_with_covariance(PoseWithCovariance(0.0, there, cov, frame_id="map"))
    payload = msgs.serialize(msg, rm.POSE_WITH_COVARIANCE)
    heard = threading.Event()

    async def script(ws: Any, c: Client) -> None:
        await c.receive(lambda: bool(c.info), {})
        channel = {"id": 3, "topic": "/initialpose", "encoding": "cdr"}
        channel["schemaName"] = rm.POSE_WITH_COVARIANCE
        await ws.send(json.dumps({"op": "advertise", "channels": [channel]}))
        await asyncio.sleep(0.2)
        await ws.send(b"\x01" + struct.pack("<I", 3) + payload)
        await asyncio.to_thread(heard.wait, 60)

    amcl = nav.runtime.localizer

    def moved() -> bool:
        pose = amcl.pose.pose
        return math.hypot(pose.x - there.x, pose.y - there.y) < 0.05

    try:
        client = Client(live.port, script)
        end = nav.now + 60.0
        live.idle(until=lambda: moved() or nav.now > end or client.done.is_set())
        heard.set()
        client.check()
    finally:
        live.close()
    pose = amcl.pose.pose
    assert math.hypot(pose.x - there.x, pose.y - there.y) < 0.05
    assert abs(pose.yaw - there.yaw) < 0.05


def test_the_cli_serves_after_the_result_until_ctrl_c(tmp_path, monkeypatch, capsys):
    served: list[FoxgloveLive] = []

    def interrupted(self: FoxgloveLive, until: Any = None, step: float = 0.1) -> None:
        served.append(self)
        raise KeyboardInterrupt

    monkeypatch.setattr(FoxgloveLive, "idle", interrupted)
    argv = ["run", str(TOUR), "-o", str(tmp_path), "--foxglove", "--foxglove-port", "0"]
    code = cli_main([*argv, "--speed", "0", "--set", "mission.time_limit=2"])
    out = capsys.readouterr().out.splitlines()
    assert code == 1  # the tour does not end in 2 s; Ctrl-C then ends the serving quietly
    (live,) = served
    assert out[0] == f"foxglove: serving ws://127.0.0.1:{live.port} " + (
        "(Foxglove: open connection, Foxglove WebSocket)"
    )
    assert out[-1].startswith(f"foxglove: still serving ws://127.0.0.1:{live.port}; ")
    assert live.server is None  # stopped
    assert (tmp_path / "report.json").is_file()
