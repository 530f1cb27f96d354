"""The `recording` output: the live view's messages, kept for `btnav view RUN_DIR`.

`outputs: [recording]` writes `recording.jsonl.gz`: one JSON message per line, as the
live page gets them (`messages`), at `rate` Hz of sim time: the `static` message first,
the map when it changes (SLAM's as it grows), the global and local costmaps at most
once a sim second when their cells changed, the tree when another runs, and a `frame`
per tick; the last frame carries the run's result. A MONITOR component that only
reads, so the run is the same with or without it; gzip keeps a tour to a few MB.
`Recording.load` reads it back for the replay.
"""

from __future__ import annotations

import gzip
import json
from pathlib import Path
from typing import IO, Any

from ...core.errors import BtnavError
from ...mission.outputs import RunOutput
from ...nav.runtime import Stage
from ...plugins import register
from .messages import StateMessages

FILE = "recording.jsonl.gz"


class RecordingWriter:
    """Writes the messages of a run at `rate` Hz of sim time (see the module doc)."""

    stage = Stage.MONITOR

    def __init__(self, nav: Any, name: str, sink: IO[str], rate: float) -> None:
        self.rate = rate
        self.sink = sink
        self.state = StateMessages(nav, name)
        self._grids_at = -1e9
        self._write(self.state.static())
        self.update(nav.now)

    def _write(self, message: dict[str, Any] | None) -> None:
        if message is not None:
            self.sink.write(json.dumps(message, separators=(",", ":")) + "\n")

    def update(self, now: float, result: str | None = None) -> None:
        state = self.state
        self._write(state.map())
        if now - self._grids_at >= 1.0:
            self._grids_at = now
            self._write(state.costmap("global"))
            self._write(state.costmap("local"))
        self._write(state.tree())
        self._write(state.frame(now, result=result, live=False))


@register("output", "recording")
class Recording:
    """Writes `recording.jsonl.gz`, what `btnav view RUN_DIR` replays."""

    files = (FILE,)
    rate = 5.0

    def __init__(self) -> None:
        self.writer: RecordingWriter | None = None
        self._file: IO[str] | None = None

    def start(self, nav: Any, out_dir: Path) -> None:
        path = Path(out_dir) / FILE
        self._file = gzip.open(path, "wt", encoding="utf-8")  # noqa: SIM115  (closed in write)
        self.writer = RecordingWriter(nav, Path(out_dir).name, self._file, self.rate)
        nav.runtime.add(self.writer, rate=self.rate)

    def write(self, run: RunOutput) -> None:
        if self.writer is None or self._file is None:
            raise BtnavError("the recording output was not started with the run")
        self.writer.update(run.navigator.now, result=run.report.status)
        self._file.close()

    @staticmethod
    def load(run_dir: str | Path) -> list[dict[str, Any]]:
        """The messages of a run's recording, in order."""
        path = Path(run_dir) / FILE
        if not path.is_file():
            raise BtnavError(
                f"{path}: no recording here; add `recording` to the mission's outputs "
                "(outputs: [report, recording]) and run it again"
            )
        with gzip.open(path, "rt", encoding="utf-8") as fp:
            return [json.loads(line) for line in fp if line.strip()]
