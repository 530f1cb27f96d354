"""Is `map -> odom -> base_link -> laser` connected? The seeds' `check_tf_tree.py`, in btnav.

    python examples/check_frames.py                      # the office mission, then a broken one
    python examples/check_frames.py MISSION [--chain map odom base_link laser]
                                            [--set KEY=VALUE ...]

A ROS user checks a robot's TF tree with `ros2 run tf2_tools view_frames`,
`tf2_echo map laser` and a script that asks `can_transform` for each link of the
chain. btnav's frame tree (`btnav.core.frames.FrameTree`) answers the same questions:
`has(frame)`, `parent(frame)`, `lookup(target, source)` (tf2's lookupTransform) and
`describe()` (view_frames as text). The robot's tree comes from its world file (REP-105
plus one frame per sensor mount); a running `Navigator` has the live one as
`nav.runtime.frames`. The check also looks at every frame the params file names
(`global_frame`, `robot_base_frame`, `base_frame_id`, ...), as `btnav frames` does.

With no MISSION it checks the office mission as it is, then the same mission with two
deliberate mistakes: the chain asks for `base_scan` (a TurtleBot's laser frame; this
robot's is `laser`) and the global costmap's `robot_base_frame` is misspelt. It exits 0
when the demo shows what it should; with a MISSION, 0 if all is connected and 1 if not.
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

from btnav.core.errors import BtnavError
from btnav.core.frames import FrameTree
from btnav.core.suggest import best_match
from btnav.mission import Mission
from btnav.mission.param_frames import frame_params, missing_frames
from btnav.params import parse_set_option

REPO = Path(__file__).resolve().parents[1]
MISSION = REPO / "missions" / "office_tour.yaml"
CHAIN = ["map", "odom", "base_link", "laser"]


def up_to_root(tree: FrameTree, frame: str) -> list[str]:
    """`frame`, its parent, its parent's parent, ... up to the root of its tree."""
    out = [frame]
    while (parent := tree.parent(out[-1])) is not None:
        out.append(parent)
    return out


def path_between(tree: FrameTree, a: str, b: str) -> list[str] | None:
    """The frames a transform from `a` to `b` goes through (tf2 chains through their
    closest common ancestor); None when they are in different trees."""
    up_a, up_b = up_to_root(tree, a), up_to_root(tree, b)
    common = next((f for f in up_a if f in up_b), None)
    if common is None:
        return None
    return up_a[: up_a.index(common) + 1] + up_b[: up_b.index(common)][::-1]


def missing_message(tree: FrameTree, frame: str, parent: str | None = None) -> str:
    """Why `frame` is missing, with a hint: what hangs under its parent in the chain (a
    sensor frame named differently), else the closest spelling (a typo in a params file)."""
    text = f"frame '{frame}' is not in the tree"
    if parent is not None and tree.has(parent):
        children = [f for f in tree.frames if f != parent and tree.parent(f) == parent]
        return text + f"; under '{parent}' there is: {', '.join(children) or 'nothing'}"
    hint = best_match(frame, tree.frames)
    return text + (f" (did you mean '{hint}'?)" if hint else f"; frames: {', '.join(tree.frames)}")


def check_chain(tree: FrameTree, chain: list[str]) -> list[str]:
    """Print each link of `chain` as connected or not; return what is missing."""
    problems: list[str] = []
    print(f"chain {' -> '.join(chain)}:")
    for parent, child in itertools.pairwise(chain):
        absent = [f for f in (parent, child) if not tree.has(f)]
        if absent:
            for frame in absent:
                if frame not in problems:
                    problems.append(frame)
            why = [missing_message(tree, f, parent if f == child else None) for f in absent]
            print(f"  {parent} -> {child}: MISSING: " + "; ".join(why))
            continue
        via = path_between(tree, parent, child)
        if via is None:
            problems.append(f"{parent} -> {child}")
            print(f"  {parent} -> {child}: NOT CONNECTED (two separate trees)")
            continue
        tf = tree.lookup(parent, child)  # tf2_echo PARENT CHILD
        print(
            f"  {parent} -> {child}: ok, through {' -> '.join(via)}"
            f"  [x {tf.x:.3f}, y {tf.y:.3f}, yaw {tf.yaw:.3f}]"
        )
    if not problems:
        tf = tree.lookup(chain[0], chain[-1])
        print(f"  {chain[-1]} in {chain[0]}: x {tf.x:.3f}, y {tf.y:.3f}, yaw {tf.yaw:.3f}")
    return problems


def check_params(mission: Mission, tree: FrameTree) -> list[str]:
    """The frames the params file names, as `btnav frames` checks them; the missing ones."""
    named = [p for p in frame_params(mission.params, mission.set_by) if p.checked]
    missing = missing_frames(mission.params, tree, mission.set_by)
    print(
        f"frames named in {Path(mission.params.path).name}: {len(named)} checked, {len(missing)} missing"
    )
    for p in missing:
        print(f"  {p.key} = {p.frame} ({p.place}): MISSING: {missing_message(tree, p.frame)}")
    return [p.frame for p in missing]


def check(mission_file: str | Path, chain: list[str], overrides: dict[str, object]) -> bool:
    """Everything above for one mission; True when all of it is connected."""
    mission = Mission.load(mission_file, overrides=overrides)
    tree = mission.frame_tree()
    print(f"== {mission.name}" + "".join(f" --set {k}={v}" for k, v in overrides.items()))
    print("frame tree (view_frames):")
    print("\n".join("  " + line for line in tree.describe().splitlines()))
    problems = check_chain(tree, chain) + check_params(mission, tree)
    if problems:
        print(f"result: NOT connected; missing: {', '.join(dict.fromkeys(problems))}")
    else:
        print("result: connected")
    return not problems


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission", nargs="?", help="a mission file (default: the demo)")
    parser.add_argument("--chain", nargs="+", default=CHAIN, help="frames from the root down")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = parser.parse_args()
    try:
        if args.mission is not None:
            overrides = dict(parse_set_option(s) for s in args.set)
            return 0 if check(args.mission, args.chain, overrides) else 1
        good = check(MISSION, CHAIN, {})
        print()
        broken_chain = [*CHAIN[:-1], "base_scan"]
        typo = {"global_costmap.global_costmap.robot_base_frame": "base_foot_print"}
        broken = check(MISSION, broken_chain, typo)
        return 0 if good and not broken else 1
    except BtnavError as err:  # a mistake in a file: one line, as the CLI prints it
        print(f"error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
