"""`btnav ...`: the command line.

A user's mistake prints one line (`btnav: error: file:line: key: message (did you mean
...?)`) and exits 2; `--debug` shows the traceback instead. A likely mistake that does
not stop the command (a `BtnavWarning`) prints `btnav: warning: file:line: ...` once.

Commands print from here, so a library user's program never gets output it did not
ask for. Each command group has a module (`run`, `batch`, `frames`, `params`, `map`,
`slam`, `tree`, `world`) holding its `*_main` and its terminal formatting; the layers
below compute, return data and raise `BtnavError`s (a run's or a batch's live progress
is drawn only on the stream a command hands them). This file parses arguments, imports
a command's module only when that command runs (so `btnav --help` stays quick), and
maps results to exit codes.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from typing import Any, TextIO

from .. import __version__
from ..core.errors import (
    ERROR_PREFIX,
    NOTE_PREFIX,
    WARNING_PREFIX,
    BtnavError,
    BtnavNote,
    BtnavWarning,
)

EXIT_OK, EXIT_FAILED, EXIT_USER_ERROR = 0, 1, 2
#: Ctrl-C, as a shell reports a process SIGINT stopped (128 + 2).
EXIT_INTERRUPTED = 130


def _params_check(args: argparse.Namespace) -> int:
    from .params import check_main

    return check_main(args.file, strict=args.strict)


def _map_show(args: argparse.Namespace) -> int:
    from .map import map_show_main

    return map_show_main(args.map, args.output)


def _map_from_world(args: argparse.Namespace) -> int:
    from .map import from_world_main

    return from_world_main(args.world, args.output, args.resolution)


def _world_show(args: argparse.Namespace) -> int:
    from .world import show_world_main

    return show_world_main(args.world, args.output)


def _world_convert(args: argparse.Namespace) -> int:
    from .world import convert_world_main

    return convert_world_main(
        args.world, args.output, args.robot, args.height_band, args.model_path or ()
    )


def _slam(args: argparse.Namespace) -> int:
    from .slam import slam_main

    return slam_main(
        args.log,
        args.params,
        args.output,
        scan_topic=args.scan_topic,
        odom_topic=args.odom_topic,
        trajectory=args.trajectory,
        lua=args.lua,
    )


def _tree_import(args: argparse.Namespace) -> int:
    from .tree import tree_import_main

    return tree_import_main(args.tree, args.output)


def _tree_show(args: argparse.Namespace) -> int:
    from .tree import tree_show_main

    return tree_show_main(args.tree)


def _tree_palette(args: argparse.Namespace) -> int:
    from .tree import tree_palette_main

    return tree_palette_main(args.output, plugins=args.plugin or (), builtin=not args.skip_builtin)


def _robot_show(args: argparse.Namespace) -> int:
    from .robot import robot_main

    return robot_main(
        args.file, args.package or (), args.arg or (), args.model_path or (), as_json=args.json
    )


def _frames_of_world(args: argparse.Namespace) -> int:
    from .world import world_frames_main

    return world_frames_main(args.world)


def _overrides(args: argparse.Namespace) -> tuple[dict[str, object], dict[str, str]]:
    """The `--set` values by key, and each key's option as typed (errors about it name that)."""
    from ..params.updates import parse_set_option

    values: dict[str, object] = {}
    origins: dict[str, str] = {}
    for text in args.set or ():
        try:
            key, value = parse_set_option(text)
        except BtnavError as err:
            raise err.located(file=f"--set {text}") from None
        values[key] = value
        origins[key] = f"--set {text}"
    return values, origins


def _packages(args: argparse.Namespace) -> AbstractContextManager[None]:
    """`--package NAME=DIR` for the descriptions the command loads."""
    from ..description.packages import command_line_packages
    from .robot import package_option

    return command_line_packages(package_option(args.package or ()))


def _run(args: argparse.Namespace) -> int:
    from .run import run_main

    overrides, origins = _overrides(args)
    with _packages(args):
        return run_main(
            args.mission,
            out=args.out,
            seed=args.seed,
            overrides=overrides,
            origins=origins,
            gif=args.gif,
            view=args.view or args.open,
            open_browser=args.open,
            speed=args.speed,
            foxglove=_foxglove_settings(args),
        )


def _view(args: argparse.Namespace) -> int:
    from .view import view_main

    return view_main(args.run_dir, open_browser=args.open)


def _foxglove_settings(args: argparse.Namespace) -> Any:
    """`--foxglove [--foxglove-host H] [--foxglove-port P] [--speed X]`, or None."""
    if not args.foxglove:
        return None
    from ..viz.foxglove_live import DEFAULT_HOST, DEFAULT_PORT, LiveSettings

    if args.speed < 0:
        raise BtnavError(f"--speed {args.speed:g}: a speed is >= 0 (0: as fast as it goes)")
    host = DEFAULT_HOST if args.foxglove_host is None else args.foxglove_host
    port = DEFAULT_PORT if args.foxglove_port is None else args.foxglove_port
    return LiveSettings(host, port, args.speed)


def _batch(args: argparse.Namespace) -> int:
    from .batch import batch_main

    overrides, origins = _overrides(args)
    return batch_main(
        args.missions,
        out=args.out,
        seeds=args.seeds,
        sweep=args.sweep or (),
        workers=args.workers,
        backend=args.backend,
        address=args.address,
        overrides=overrides,
        origins=origins,
    )


def _frames_of_mission(args: argparse.Namespace) -> int:
    from .frames import frames_main

    with _packages(args):
        return frames_main(args.mission, *_overrides(args))


class _Parser(argparse.ArgumentParser):
    """Usage mistakes exit 2 with one line, like every other user error."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USER_ERROR, f"{ERROR_PREFIX}{message} (see '{self.prog} --help')\n")


def _group(sub: Any, name: str, help: str) -> Any:
    """A command group (`btnav tree ...`): its own subcommands, one of which is required."""
    group = sub.add_parser(name, help=help)
    return group.add_subparsers(dest=f"{name}_command", required=True, parser_class=_Parser)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="btnav", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"btnav {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks for user errors")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    set_help = (
        "override a param (local_costmap.local_costmap.inflation_layer.inflation_radius=0.4) "
        "or a mission key (mission.seed=3); repeatable"
    )
    package_help = (
        "a ROS package's folder, for $(find NAME) and package:// in the robot's "
        "description (before the world's package_paths); repeatable"
    )
    run = sub.add_parser("run", help="run a mission; exit 0 succeeded, 1 failed, 2 user error")
    run.add_argument("mission", help="the mission .yaml")
    run.add_argument(
        "-o",
        "--out",
        help="the folder for report.json, trajectory.csv, bt_log.jsonl "
        "(default: out/<mission name>)",
    )
    run.add_argument("--seed", type=int, help="the seed (default: the mission's)")
    run.add_argument("--set", action="append", metavar="KEY=VALUE", help=set_help)
    run.add_argument(
        "--gif", action="store_true", help="also write run.gif, the run animated (viz extra)"
    )
    run.add_argument(
        "--view",
        action="store_true",
        help="watch and steer the run in a browser page on 127.0.0.1 (view extra); "
        "it keeps serving after the run, until Ctrl-C",
    )
    run.add_argument("--open", action="store_true", help="with --view: open the default browser")
    run.add_argument(
        "--speed",
        type=float,
        default=1.0,
        help="with --view or --foxglove: sim seconds per wall second (default 1; 0: as fast as it goes)",
    )
    run.add_argument("--package", action="append", metavar="NAME=DIR", help=package_help)
    _foxglove_arguments(run)
    run.set_defaults(func=_run)

    view = sub.add_parser(
        "view", help="replay a run's recording (outputs: [recording]) in a browser page"
    )
    view.add_argument("run_dir", help="the run's folder (holding recording.jsonl.gz)")
    view.add_argument("--open", action="store_true", help="open the default browser")
    view.set_defaults(func=_view)

    batch = sub.add_parser(
        "batch",
        help="run missions x seeds x swept params in parallel, resumably; "
        "exit 0 all succeeded, 1 any failed, 2 user error",
    )
    batch.add_argument("missions", nargs="+", metavar="MISSION", help="mission .yaml files")
    batch.add_argument(
        "-o", "--out", required=True, help="the folder for results.csv, the summary and runs/"
    )
    batch.add_argument(
        "--seeds",
        metavar="A:B",
        help="seeds A..B-1 (0:100 is 100 seeds), or N, or N1,N2,... (default: each mission's)",
    )
    batch.add_argument(
        "--sweep",
        action="append",
        metavar="KEY=V1,V2",
        help="a --set key and its values (0.3,0.5) or range (0.3:0.7:0.1, stop included); "
        "repeatable: the runs are the product",
    )
    batch.add_argument("--set", action="append", metavar="KEY=VALUE", help=set_help)
    batch.add_argument(
        "--workers", type=int, help="runs at once (default: every core; with Ray, its CPUs)"
    )
    batch.add_argument(
        "--backend",
        choices=("local", "ray"),
        default="local",
        help="local: a process pool; ray: Ray tasks (the ray extra)",
    )
    batch.add_argument("--address", help="a running Ray cluster's address (default: a local Ray)")
    batch.set_defaults(func=_batch)

    frames_cmd = sub.add_parser(
        "frames", help="print a mission's frame tree and check every frame its params name"
    )
    frames_cmd.add_argument("mission", help="the mission .yaml")
    frames_cmd.add_argument("--set", action="append", metavar="KEY=VALUE", help=set_help)
    frames_cmd.add_argument("--package", action="append", metavar="NAME=DIR", help=package_help)
    frames_cmd.set_defaults(func=_frames_of_mission)

    params = _group(sub, "params", "Nav2 params files")
    check = params.add_parser(
        "check", help="validate a params file; list servers, plugins and ignored keys"
    )
    check.add_argument("file")
    check.add_argument(
        "--strict",
        action="store_true",
        help="a key Nav2 skips (a ROS 1 name, an older distribution's, a BT port) is an error",
    )
    check.set_defaults(func=_params_check)

    maps = _group(sub, "map", "map_server maps")
    fw = maps.add_parser("from-world", help="rasterise a world's static geometry into a map")
    fw.add_argument("world")
    fw.add_argument("-o", "--output", required=True, help="the map .yaml to write (and its .pgm)")
    fw.add_argument("--resolution", type=float, default=0.05, help="metres per cell (0.05)")
    fw.set_defaults(func=_map_from_world)
    ms = maps.add_parser("show", help="draw a map (free, occupied, unknown) into a PNG (viz extra)")
    ms.add_argument("map", help="a map_server .yaml")
    ms.add_argument("-o", "--output", help="the .png to write (default: beside the map)")
    ms.set_defaults(func=_map_show)

    slam = sub.add_parser("slam", help="SLAM on a recorded log (CARMEN, ROS 1 or ROS 2 bag)")
    slam.add_argument("log", help="a .clf/.log CARMEN file, a .bag, or a rosbag2 folder/.db3/.mcap")
    engine = slam.add_mutually_exclusive_group()
    engine.add_argument("--params", help="a params file with a slam_toolbox: section (defaults)")
    engine.add_argument("--lua", help="run Cartographer, configured by this .lua options file")
    slam.add_argument("-o", "--output", required=True, help="the folder to write")
    slam.add_argument("--scan-topic", help="the LaserScan topic of a bag (when several)")
    slam.add_argument("--odom-topic", help="the Odometry topic of a bag (when several)")
    slam.add_argument(
        "--trajectory",
        choices=("matched", "odometry"),
        help="slam_toolbox's trajectory.csv: every scan matched to the map (default), or "
        "odometry between nodes (Cartographer's: every scan as local SLAM matched it)",
    )
    slam.set_defaults(func=_slam)

    tree = _group(sub, "tree", "behaviour trees (Nav2 XML or btnav YAML)")
    imp = tree.add_parser("import", help="spell a Nav2 XML tree in btnav's YAML")
    imp.add_argument("tree", help="the Nav2 .xml file")
    imp.add_argument("-o", "--output", help="the .yaml to write (default: print it)")
    imp.set_defaults(func=_tree_import)
    show = tree.add_parser("show", help="print a tree with its ports")
    show.add_argument("tree", help="a .xml/.yaml file or a bundled tree's name")
    show.set_defaults(func=_tree_show)
    palette = tree.add_parser(
        "palette", help="write Groot2's node palette (TreeNodesModel) of every node type"
    )
    palette.add_argument("-o", "--output", help="the .xml to write (default: print it)")
    palette.add_argument(
        "--plugin",
        action="append",
        metavar="MODULE_OR_FILE",
        help="load a plugin module or .py file first, so its nodes are in it; repeatable",
    )
    palette.add_argument(
        "--skip-builtin",
        action="store_true",
        help="leave out BehaviorTree.CPP's own nodes (Sequence, Inverter, ...): Groot2 has them",
    )
    palette.set_defaults(func=_tree_palette)

    world = _group(sub, "world", "simulation worlds")
    show = world.add_parser("show", help="draw the world, the robot and one scan (viz extra)")
    show.add_argument("world")
    show.add_argument("-o", "--output", required=True, help="the PNG to write")
    show.set_defaults(func=_world_show)
    frames = world.add_parser("frames", help="print the robot's frame tree (REP-105)")
    frames.add_argument("world")
    frames.set_defaults(func=_frames_of_world)
    conv = world.add_parser("convert", help="write a Gazebo SDF world as a btnav world YAML")
    conv.add_argument("world", help="a Gazebo .world or .sdf file (or a world YAML with sdf:)")
    conv.add_argument("-o", "--output", required=True, help="the world .yaml to write")
    conv.add_argument(
        "--robot",
        metavar="FILE",
        help="a URDF, xacro or SDF description: the robot block written, and the lidar "
        "height the height band comes from (default: btnav's default robot)",
    )
    conv.add_argument(
        "--height-band",
        nargs=2,
        type=float,
        metavar=("LO", "HI"),
        help="keep the geometry between these heights (m; default: 0.05 to the lidar + 0.1)",
    )
    conv.add_argument(
        "--model-path",
        action="append",
        metavar="DIR",
        help="a folder model:// is looked up in (before GZ_SIM_RESOURCE_PATH); repeatable",
    )
    conv.set_defaults(func=_world_convert)

    robot = _group(sub, "robot", "robot descriptions (URDF, xacro, Gazebo SDF)")
    rshow = robot.add_parser("show", help="print what btnav reads from a robot description")
    rshow.add_argument(
        "file", help="a .urdf, .xacro or model.sdf, a Gazebo model folder, or model://NAME"
    )
    rshow.add_argument(
        "--package",
        action="append",
        metavar="NAME=DIR",
        help="a ROS package's folder, for $(find NAME); repeatable",
    )
    rshow.add_argument(
        "--arg", action="append", metavar="NAME=VALUE", help="a xacro arg; repeatable"
    )
    rshow.add_argument(
        "--model-path",
        action="append",
        metavar="DIR",
        help="a folder model:// is looked up in; repeatable",
    )
    rshow.add_argument("--json", action="store_true", help="print one JSON object")
    rshow.set_defaults(func=_robot_show)
    return parser


def _warning_printer(python_show: Callable[..., None]) -> Callable[..., None]:
    """`warnings.showwarning` for a command: a `BtnavWarning` is one line, `btnav: warning:
    file:line: ...` (`btnav: note:` for a `BtnavNote`); any other warning is shown as Python (`python_show`) would."""

    def show(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: TextIO | None = None,
        line: str | None = None,
    ) -> None:
        if issubclass(category, BtnavWarning):
            prefix = NOTE_PREFIX if issubclass(category, BtnavNote) else WARNING_PREFIX
            print(f"{prefix}{message}", file=file or sys.stderr)
        else:
            python_show(message, category, filename, lineno, file, line)

    return show


def _foxglove_arguments(run: argparse.ArgumentParser) -> None:
    run.add_argument(
        "--foxglove",
        action="store_true",
        help="serve the run live to Foxglove (WebSocket; the view extra); a /goal_pose it "
        "publishes is a goal; after the task it keeps serving until Ctrl-C",
    )
    run.add_argument("--foxglove-host", help="the server's address (default: 127.0.0.1)")
    run.add_argument(
        "--foxglove-port", type=int, help="the server's port (default: 8765; 0: a free one)"
    )


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    func: Callable[[argparse.Namespace], int] = args.func
    with warnings.catch_warnings():
        warnings.simplefilter("default", BtnavWarning)  # each distinct warning once
        warnings.showwarning = _warning_printer(warnings.showwarning)
        try:
            return func(args)
        except BtnavError as err:
            if args.debug:
                raise
            print(f"{ERROR_PREFIX}{err}", file=sys.stderr)
            return EXIT_USER_ERROR
        except OSError as err:  # a folder or file of the user's that cannot be written or read
            if args.debug:
                raise
            where = f"{err.filename}: " if err.filename else ""
            print(f"{ERROR_PREFIX}{where}{err.strerror or err}", file=sys.stderr)
            return EXIT_USER_ERROR
        except KeyboardInterrupt:
            return EXIT_INTERRUPTED
