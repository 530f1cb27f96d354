"""`btnav view RUN_DIR`: a run's recording in the live page, with a time slider.

The page sends `seek` (a frame's index); the server answers with the grids and the
tree that held at that frame (those the page does not have yet) and the frame itself.
Everything runs on the server's thread: a replay has no sim.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .hub import Hub
from .recording import Recording


class Replay:
    """A recording's messages, indexed by frame, served to the page."""

    def __init__(self, run_dir: str | Path) -> None:
        messages = Recording.load(run_dir)
        self.static = next((m for m in messages if m["type"] == "static"), None)
        self.frames: list[dict[str, Any]] = []
        #: per frame, the latest map, costmaps and tree before it (as indices in `held`)
        self.held: list[dict[str, Any]] = []
        self._context: list[dict[str, int]] = []
        latest: dict[str, int] = {}
        for message in messages:
            kind = message["type"]
            if kind == "frame":
                message["index"] = len(self.frames)
                self.frames.append(message)
                self._context.append(dict(latest))
            elif kind in ("map", "costmap", "tree"):
                key = f"costmap:{message['which']}" if kind == "costmap" else kind
                latest[key] = len(self.held)
                self.held.append(message)
        self.hub = Hub(self.command)
        self._sent: dict[str, int] = {}

    def start(self) -> Replay:
        self.hub.start()
        return self

    @property
    def url(self) -> str:
        return self.hub.url

    def command(self, command: dict[str, Any]) -> None:
        """The page's command (on the server's thread)."""
        cmd = command.get("cmd")
        if cmd == "hello":
            self._sent = {}
            if self.static is not None:
                self.hub.publish(self.static)
            times = [f["t"] for f in self.frames]
            rate = (len(times) - 1) / (times[-1] - times[0]) if len(times) > 1 else 5.0
            self.hub.publish({"type": "replay", "count": len(self.frames), "rate": round(rate, 3)})
            self.seek(0)
        elif cmd == "seek":
            self.seek(int(command.get("index", 0)))

    def seek(self, index: int) -> None:
        if not self.frames:
            return
        index = min(max(index, 0), len(self.frames) - 1)
        for key, held in self._context[index].items():
            if self._sent.get(key) != held:
                self._sent[key] = held
                self.hub.publish(self.held[held])
        self.hub.publish(self.frames[index])

    def close(self) -> None:
        self.hub.stop()
