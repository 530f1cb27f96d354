"""Map a corridor with SLAM for a while, then save the map: the seeds' `map_saver.py`, in btnav.

    python examples/save_map.py [--seconds 20] [--out out/examples/save_map] [--mission FILE]

A ROS user maps with slam_toolbox while driving, then runs
`ros2 run nav2_map_server map_saver_cli -f my_map` (or calls map_saver's service from a
script) and gets `my_map.yaml` + `my_map.pgm`. Here the bundled
`missions/corridor_loop_slam.yaml` (`localization: slam`) drives its waypoints round
the corridor loop for `--seconds` of sim time while SLAM builds the map; then
`nav.save_map(path)` writes what map_saver writes (trinary mode, the `map_saver:`
section's thresholds), and the script reads it back with `load_map`, as map_server
would, to print its size, resolution, origin and free / occupied / unknown cells.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from btnav import Navigator
from btnav.maps import FREE, OCCUPIED, UNKNOWN, load_map

REPO = Path(__file__).resolve().parents[1]
MISSION = REPO / "missions" / "corridor_loop_slam.yaml"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="sim seconds of mapping")
    parser.add_argument("--out", default="out/examples/save_map", help="folder for map.yaml/.pgm")
    parser.add_argument("--mission", default=str(MISSION), help="a mission with SLAM")
    args = parser.parse_args()

    nav = Navigator.from_mission(args.mission)
    waypoints = nav.mission.spec.task.follow_waypoints or []
    print(f"brought up {nav.mission.name} (localization: {nav.mission.spec.localization})")
    nav.follow_waypoints(waypoints)  # waypoint_follower drives while SLAM maps

    # Watch the map grow: every 5 sim seconds, the map SLAM gives map_server so far.
    next_print = 5.0
    while nav.now < args.seconds and not nav.is_task_complete():  # each poll: 0.1 s
        if nav.now >= next_print:
            next_print += 5.0
            grid = nav.stack.map_server.map
            size = f"{grid.width} x {grid.height} cells" if grid is not None else "no map yet"
            feedback = nav.get_feedback()  # FollowWaypoints' feedback: the current waypoint
            print(
                f"  t={nav.now:5.1f} s  waypoint {feedback.current_waypoint + 1} of "
                f"{len(waypoints)}  map {size}"
            )
    nav.cancel_task()  # stop driving (a user's Ctrl-C on teleop); the map stays
    print(f"stopped at t={nav.now:.1f} s")

    # `ros2 run nav2_map_server map_saver_cli -f OUT/map`
    yaml_file, image_file = nav.save_map(Path(args.out) / "map")
    print(f"saved {yaml_file} and {image_file.name}:")
    print("\n".join("  " + line for line in yaml_file.read_text().splitlines()))

    # Read it back as map_server would, and count what it holds.
    grid = load_map(yaml_file)
    width_m, height_m = grid.size_m
    print(f"size: {grid.width} x {grid.height} cells, {width_m:.2f} x {height_m:.2f} m")
    print(
        f"resolution: {grid.resolution:.3f} m/cell, origin ({grid.origin.x:.2f}, {grid.origin.y:.2f})"
    )
    total = grid.data.size
    for name, value in (("free", FREE), ("occupied", OCCUPIED), ("unknown", UNKNOWN)):
        n = int(np.count_nonzero(grid.data == value))
        print(f"{name} cells: {n} ({100.0 * n / total:.1f}%)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
