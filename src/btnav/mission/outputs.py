"""A run's outputs: the built-in files, and `output` plugins for everything else.

`report`, `trajectory`, `bt_log`, `map` and `pose_graph` are written by the run itself;
`pose_graph` is slam_toolbox's SerializePoseGraph at the end of a `localization: slam`
run (`pose_graph.npz`, as `btnav slam -o` writes it), which a later mission loads with
slam_toolbox's `map_file_name` (`mode: localization`, or `mapping` to continue the map). Any other
name in a mission's `outputs:` is an `output` plugin (`@register("output", "png")`),
called once the run has ended with a `RunOutput`; `files` lists what it writes.
An output that records the run as it goes (a GIF's frames, a bag's messages) also
defines `start(nav, out_dir)`, called once the bring-up is built and before the task
is sent: it adds its own runtime components (MONITOR stage, read-only) there.
The `viz` extra registers `png` (`run.png`) and `gif` (`run.gif`), and `bag` (a ROS 2
bag, with the `logs` extra). A user's output is a peer:

```python
@register("output", "speed_plot")
class SpeedPlot:
    files = ("speed.png",)

    def write(self, run: RunOutput) -> None:
        ...  # run.track, run.plan, run.report, run.navigator, run.out_dir
```
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from ..core.suggest import best_match
from ..plugins import is_registered, lookup, names
from .errors import MissionError

#: Written by the run itself, and the files each one is.
BUILTIN_OUTPUTS: dict[str, tuple[str, ...]] = {
    "report": ("report.json",),
    "trajectory": ("trajectory.csv",),
    "bt_log": ("bt_log.jsonl",),
    "map": ("map.yaml", "map.pgm"),
    "pose_graph": ("pose_graph.npz",),
}
#: Outputs only some localisers can give, and which (`localization:` values).
OUTPUT_NEEDS: dict[str, tuple[str, ...]] = {"pose_graph": ("slam_toolbox",)}
DEFAULT_OUTPUTS = ["report", "trajectory", "bt_log"]


@dataclass
class RunOutput:
    """What an output plugin gets once a run has ended."""

    out_dir: Path
    mission: Any  # Mission
    navigator: Any  # Navigator, its world and stack as the run left them
    report: Any  # RunReport
    track: np.ndarray  # one row per control cycle: t, gt_x, gt_y, gt_yaw, est_x, est_y, est_yaw

    @property
    def plan(self) -> np.ndarray:
        """(N, 3) x, y, yaw: the last global plan the controller followed; (0, 3) if none.

        Read from controller_server's last FollowPath goal, which the run leaves in place.
        """
        handle = self.navigator.stack.controller_server.action.current
        if handle is None or handle.goal.path is None:
            return np.zeros((0, 3))
        return np.asarray(handle.goal.path.poses, dtype=float).reshape(-1, 3).copy()


class OutputPlugin(Protocol):
    files: tuple[str, ...]

    def write(self, run: RunOutput) -> None: ...


def start_outputs(plugins: Mapping[str, Any], nav: Any, out_dir: Path) -> None:
    """Call each plugin's optional `start(nav, out_dir)` before the task is sent."""
    for plugin in plugins.values():
        start = getattr(plugin, "start", None)
        if start is not None:
            start(nav, out_dir)


def output_names() -> list[str]:
    return [*BUILTIN_OUTPUTS, *(n for n in names("output") if n not in BUILTIN_OUTPUTS)]


def is_output(name: str) -> bool:
    return name in BUILTIN_OUTPUTS or is_registered("output", name)


def output_files(name: str) -> tuple[str, ...]:
    if name in BUILTIN_OUTPUTS:
        return BUILTIN_OUTPUTS[name]
    return tuple(lookup("output", name).files)


def output_plugin(name: str) -> OutputPlugin:
    return lookup("output", name)()


def check_outputs(wanted: list[str], where: Callable[[int], dict[str, Any]]) -> None:
    """Each name is a built-in output or a registered `output` plugin; `where(i)` locates item i."""
    for i, name in enumerate(wanted):
        if is_output(name):
            continue
        raise MissionError(
            f"unknown output '{name}'; outputs are {', '.join(output_names())}",
            suggestion=best_match(name, output_names()),
            **where(i),
        )
