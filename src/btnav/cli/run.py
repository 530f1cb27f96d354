"""`btnav run MISSION [--out DIR] [--seed N] [--set KEY=VALUE ...] [--gif]`: the run, one line
of result, then one line per missed waypoint (its pose, Nav2's error code and message, the
tree node that failed last, the sim time). `--gif` adds the `gif` output (`run.gif`, the
viz extra) to the mission's outputs. `--view` serves the live view (the view extra) on
127.0.0.1, paced to `--speed` times the wall clock, and keeps it serving after the run. `--foxglove` serves the run live to Foxglove
(`viz.foxglove_live`) and, after the result, keeps serving (and running the goals a
client sends) until Ctrl-C.

On a terminal a live status line (sim time, real-time factor, the running action,
the waypoint) is redrawn while the run goes and erased before the result; elsewhere
the output is only the result.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from ..core.errors import BtnavError
from ..mission.mission import Mission
from ..mission.runner import run_mission
from ..mission.stages import is_staged, run_stages, staged_mission_name
from .status_line import StatusLine


def default_out_dir(mission: Mission) -> Path:
    return Path("out") / mission.name


def run_main(
    path: str,
    *,
    out: str | None = None,
    seed: int | None = None,
    overrides: dict[str, Any] | None = None,
    origins: dict[str, str] | None = None,
    gif: bool = False,
    view: bool = False,
    open_browser: bool = False,
    speed: float = 1.0,
    foxglove: Any = None,
) -> int:
    """Exit 0 when the task succeeded, 1 when it failed, hit its time limit or missed
    waypoints. `origins` maps each override key to the `--set KEY=VALUE` that gave it.
    With `view` the run is shown live (and kept serving after its end, until Ctrl-C);
    `foxglove` (a `LiveSettings`) serves the run to Foxglove."""
    if view and foxglove is not None:
        raise BtnavError("--view and --foxglove: one viewer at a time")
    if is_staged(path):
        if view:
            raise BtnavError(f"{path}: --view shows one mission; a mission in stages is not one")
        if foxglove is not None:
            raise BtnavError(f"{path}: --foxglove serves one mission, not a staged one")
        return _run_stages(path, out, seed, overrides, origins, gif)
    mission = Mission.load(path, seed=seed, overrides=overrides, origins=origins)
    if gif and "gif" not in mission.spec.outputs:
        mission.spec.outputs = [*mission.spec.outputs, "gif"]
    out_dir = Path(out) if out is not None else default_out_dir(mission)
    live = _live_view(mission, speed, open_browser) if view else None
    fox = None if foxglove is None else _foxglove_output(foxglove)
    status = StatusLine(sys.stdout, task=mission.task, goals=len(mission.spec.task.poses))
    try:
        attach = None if live is None else lambda nav: live.attach(nav, mission)
        report = run_mission(
            mission,
            out_dir,
            progress=status if status.enabled else None,
            attach=attach,
            plugins=None if fox is None else {"foxglove": fox},
        )
    finally:
        status.close()
    print(report.summary())
    for line in report.missed_lines():
        print(f"  {line}")
    if report.outputs:
        print(f"outputs in {out_dir}/: {', '.join(report.outputs)}")
    if live is not None:
        _keep_serving(live, report.status)
    elif fox is not None and fox.live is not None:
        _serve_on(fox.live)
    return report.exit_code


def _live_view(mission: Mission, speed: float, open_browser: bool) -> Any:
    from ..viz.live.live_view import LiveView

    if speed < 0:
        raise BtnavError(f"--speed must be >= 0 (0: as fast as it goes), not {speed:g}")
    live = LiveView(speed).start()
    print(f"live view at {live.url} (speed {speed:g}x; Ctrl-C to stop)", flush=True)
    if open_browser:
        import webbrowser

        webbrowser.open(live.url)
    return live


def _keep_serving(live: Any, result: str) -> None:
    """After the run: the sim idles and the page stays up for more goals, until Ctrl-C."""
    live.result = result
    _idle_until_ctrl_c(
        live,
        f"the run has ended; {live.url} keeps serving: "
        "drag a 2D Goal Pose to drive on, Ctrl-C to stop",
    )


def _foxglove_output(settings: Any) -> Any:
    """The `foxglove` output with the flags' settings, left serving after the run."""
    from ..viz.foxglove_live import FoxgloveOutput

    def serving(live: Any) -> None:
        print(f"foxglove: serving {live.url} (Foxglove: open connection, Foxglove WebSocket)")

    return FoxgloveOutput(settings, keep_serving=True, serving=serving)


def _serve_on(live: Any) -> None:
    """After the result: keep the sim and the server going for clicked goals, until Ctrl-C."""
    _idle_until_ctrl_c(
        live, f"foxglove: still serving {live.url}; goals sent on /goal_pose run; Ctrl-C to stop"
    )


def _idle_until_ctrl_c(live: Any, line: str) -> None:
    """Say so, then let a viewer (`--view`, `--foxglove`) idle the sim on until Ctrl-C."""
    print(line, flush=True)
    try:
        live.idle()
    except KeyboardInterrupt:
        pass
    finally:
        live.close()


def _run_stages(
    path: str,
    out: str | None,
    seed: int | None,
    overrides: dict[str, Any] | None,
    origins: dict[str, str] | None,
    gif: bool,
) -> int:
    """A mission in stages: a result line per stage as it ends, outputs in a folder each."""
    out_dir = Path(out) if out is not None else Path("out") / staged_mission_name(path)
    statuses: list[StatusLine] = []

    def progress(mission: Mission) -> Any:
        status = StatusLine(sys.stdout, task=mission.task, goals=len(mission.spec.task.poses))
        statuses.append(status)
        return status if status.enabled else None

    def ended(stage: str, report: Any) -> None:
        statuses[-1].close()
        print(f"[{stage}] {report.summary()}")
        for line in report.missed_lines():
            print(f"[{stage}]   {line}")
        print(f"[{stage}] outputs in {out_dir / stage}/: {', '.join(report.outputs)}")

    extra = {"gif"} if gif else set()
    staged = run_stages(
        path,
        out_dir,
        seed=seed,
        overrides=overrides,
        origins=origins,
        progress=progress,
        on_stage=ended,
        extra_outputs=extra,
    )
    for name in staged.planned[len(staged.stages) :]:
        print(f"[{name}] not run: an earlier stage did not succeed")
    return staged.exit_code
