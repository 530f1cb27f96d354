"""`btnav run --view`: the MONITOR component that shows the run in the page and steers it.

Each update (at `RATE` Hz of sim time) the view, in the sim thread, applies what the
page asked since the last one (a queue filled by the server's thread): "2D Goal Pose"
sends NavigateToPose through the navigator API, "2D Pose Estimate" sets the
localiser's initial pose, pause / step / speed change the pacing. Then it holds the
step while paused, waits on the `Pacer` (wall time times the speed) and, when a page
is connected, sends a frame (at most `FRAME_HZ` per wall second) and what changed.
With no page and no click it only reads and sleeps, so the trajectory is the same bytes
as a run without it. After the task ends `idle` keeps stepping the sim (paced) so the
user can send more goals, until Ctrl-C.
"""

from __future__ import annotations

import queue
import threading
import time
from typing import Any

from ...core.geometry import Pose2D
from ...nav.runtime import Stage
from ..pacing import Pacer
from .hub import Hub
from .messages import StateMessages

#: Sim-time updates per second (pacing, clicks and single steps have this grain).
RATE = 20.0
#: Frames sent per wall second at most; costmaps and SLAM maps at most once a second.
FRAME_HZ = 30.0
GRID_PERIOD = 1.0


class LiveView:
    """Paces the run, applies the page's commands and sends it the run's state."""

    stage = Stage.MONITOR
    rate = RATE

    def __init__(self, speed: float = 1.0, hub: Hub | None = None) -> None:
        self.pacer = Pacer(speed)
        self.commands: queue.Queue[dict[str, Any]] = queue.Queue()
        self.hub = hub if hub is not None else Hub(self.commands.put)
        self.paused = False
        self.steps = 0  # single steps asked while paused
        self.costmap = "none"
        self.nav: Any = None
        self.state: StateMessages | None = None
        self.result: str | None = None
        self._sent_at = -1e9
        self._grid_at = -1e9
        self._rtf: tuple[float, float, float] = (0.0, 0.0, 0.0)  # (sim, wall, factor)
        self._clock = time.monotonic
        self._closed = threading.Event()

    @property
    def url(self) -> str:
        return self.hub.url

    def start(self) -> LiveView:
        self.hub.start()
        return self

    def attach(self, nav: Any, mission: Any) -> None:
        """Watch `nav` (called by `run_mission` before the task is sent)."""
        self.nav = nav
        self.state = StateMessages(nav, mission.name)
        nav.runtime.add(self, stage=Stage.MONITOR, rate=RATE)

    def update(self, now: float) -> None:
        self._apply_commands(now)
        while self.paused and not self.steps and not self._closed.is_set():
            self._publish(now, force=True)
            self._wait_for_command(now)
        if self.steps:
            self.steps -= 1
        self.pacer.wait(now)
        self._publish(now)
        if self._closed.is_set():
            self.pacer.speed = 0  # a closed view holds nothing back

    def idle(self) -> None:
        """Keep the sim going (paced; at most 1x with no task) for more goals, until Ctrl-C
        (or `close`)."""
        rt = self.nav.runtime
        while not self._closed.is_set():
            busy = self.nav.handle is not None and not self.nav.handle.done
            if self.pacer.speed == 0 and not busy:
                time.sleep(1.0 / RATE)
            rt.spin_for(1.0 / RATE)

    def close(self) -> None:
        """Stop serving; a paused or idling sim thread returns."""
        self._closed.set()
        self.hub.stop()

    # -- the page's commands, applied in the sim thread ----------------------------------

    def _wait_for_command(self, now: float) -> None:
        try:
            command = self.commands.get(timeout=0.1)
        except queue.Empty:
            return
        self._apply(command, now)
        self._apply_commands(now)

    def _apply_commands(self, now: float) -> None:
        while True:
            try:
                command = self.commands.get_nowait()
            except queue.Empty:
                return
            self._apply(command, now)

    def _apply(self, command: dict[str, Any], now: float) -> None:
        cmd = command.get("cmd")
        if cmd == "hello" and self.state is not None:
            self.state.reset()
            self.hub.publish(self.state.static())
            self._publish(now, force=True)
        elif cmd == "pause":
            self.paused = True
        elif cmd == "resume":
            self.paused = False
            self.pacer.reanchor()
        elif cmd == "step":
            self.steps += 1
            self.pacer.reanchor()
        elif cmd == "speed":
            self.pacer.speed = max(float(command.get("value", 1.0)), 0.0)
        elif cmd == "costmap":
            self.costmap = str(command.get("which", "none"))
            self._grid_at = -1e9
        elif cmd == "goal" and self.nav is not None:
            self.nav.go_to_pose(Pose2D(*map(float, command["pose"][:3])))
        elif cmd == "initial_pose" and self.nav is not None:
            self.nav.set_initial_pose(Pose2D(*map(float, command["pose"][:3])))

    # -- what the page is sent ----------------------------------------------------------

    def _publish(self, now: float, force: bool = False) -> None:
        if not self.hub.connected or self.state is None:
            return
        wall = self._clock()
        if not force and wall - self._sent_at < 1.0 / FRAME_HZ:
            return
        self._sent_at = wall
        state = self.state
        if wall - self._grid_at >= GRID_PERIOD:
            self._grid_at = wall
            for message in (state.map(), self._costmap()):
                if message is not None:
                    self.hub.publish(message)
        tree = state.tree()
        if tree is not None:
            self.hub.publish(tree)
        self.hub.publish(
            state.frame(
                now,
                rtf=self._real_time_factor(now, wall),
                paused=self.paused,
                speed=self.pacer.speed,
                result=self.result,
                live=True,
            )
        )

    def _costmap(self) -> dict[str, Any] | None:
        if self.costmap not in ("global", "local") or self.state is None:
            return None
        return self.state.costmap(self.costmap)

    def _real_time_factor(self, now: float, wall: float) -> float:
        """Sim seconds per wall second, over the last second or so."""
        sim0, wall0, factor = self._rtf
        if wall - wall0 >= 1.0:
            factor = (now - sim0) / (wall - wall0) if wall0 else 0.0
            self._rtf = (now, wall, factor)
        return round(factor, 2)
