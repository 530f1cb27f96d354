"""Whole missions through `btnav run`: what a user sees in the report, trajectory and tick log."""

from __future__ import annotations

import csv
import itertools
import json
import math
import platform
from pathlib import Path

import pytest

import btnav
from btnav.cli import main
from btnav.core.error_codes import ComputePathToPoseError
from btnav.mission import Mission, run_mission
from btnav.mission.trajectory import COLUMNS

from .missions import REPO, TOLERANCE, TOUR, read_report, write_mission

pytestmark = pytest.mark.slow


def trajectory(out: Path) -> list[dict[str, float]]:
    with open(out / "trajectory.csv") as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def bt_log(out: Path) -> list[dict]:
    return [json.loads(line) for line in (out / "bt_log.jsonl").read_text().splitlines()]


@pytest.mark.parametrize("seed", [0, 1])
def test_the_office_tour_with_nav2s_xml_tree_reaches_every_waypoint_untouched(
    tmp_path, nav2_dir, capsys, seed
):
    tree = nav2_dir / "behavior_trees" / "navigate_to_pose_w_replanning_and_recovery.xml"
    tour = Mission.load(TOUR)
    path = write_mission(
        tmp_path,
        "tour",
        tree=str(tree),
        initial_pose=list(tour.spec.initial_pose),
        task={"follow_waypoints": [list(p) for p in tour.spec.task.poses]},
        time_limit=300,
        seed=seed,
    )
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("tour: succeeded") and str(out) in printed

    report = read_report(out)
    assert report["status"] == "succeeded" and report["error_code"] is None
    assert report["collisions"] == 0 and report["missed_waypoints"] == []
    assert report["localization_error"]["max_xy"] < 0.05  # ground truth, up to odometry lag
    rows = trajectory(out)
    assert list(rows[0]) == list(COLUMNS)
    assert len(rows) == pytest.approx(report["sim_time"] * 20, abs=2)  # controller_frequency
    # every waypoint reached, in order
    t_reached = []
    for x, y, _ in tour.spec.task.poses:
        near = [r["t"] for r in rows if math.hypot(r["gt_x"] - x, r["gt_y"] - y) <= TOLERANCE]
        assert near, f"waypoint ({x}, {y}) never reached"
        t_reached.append(min(t for t in near if not t_reached or t > t_reached[-1]))
    assert t_reached == sorted(t_reached)
    steps = [
        math.hypot(b["gt_x"] - a["gt_x"], b["gt_y"] - a["gt_y"])
        for a, b in itertools.pairwise(rows)
    ]
    assert report["path_length"] == pytest.approx(sum(steps), rel=1e-6)
    assert max(abs(r["cmd_v"]) for r in rows) <= 0.5 + 1e-9  # MPPI's vx_max in Nav2's file

    log = bt_log(out)
    names = {e["node_name"] for e in log}
    assert any(n.endswith("NavigateRecovery") for n in names)
    assert any(n.endswith("FollowPath") for n in names)
    assert {e["current_status"] for e in log} <= {"IDLE", "RUNNING", "SUCCESS", "FAILURE"}
    roots = [e for e in log if e["uid"] == 0 and e["current_status"] == "SUCCESS"]
    assert len(roots) == 4  # the tree succeeded once per waypoint
    assert all(a["timestamp"] <= b["timestamp"] for a, b in itertools.pairwise(log))


def test_an_unreachable_goal_fails_with_nav2s_code_after_the_recoveries(tmp_path):
    path = write_mission(tmp_path, "unreachable", task={"navigate_to_pose": [6.5, 1.2, 0.0]})
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 1
    report = read_report(out)
    assert report["status"] == "failed"
    assert report["error_code"] == ComputePathToPoseError.NO_VALID_PATH
    assert report["error_msg"]
    assert report["recoveries"] >= 6  # the RecoveryNode's number_of_retries, and more inside
    assert report["collisions"] == 0 and report["replans"] == 0
    log = bt_log(out)
    ran = {e["node_name"].rsplit(".", 1)[-1] for e in log if e["current_status"] == "RUNNING"}
    assert {"Spin", "Wait", "BackUp"} <= ran  # the recovery branch's RoundRobin went round
    assert [e for e in log if e["uid"] == 0][-1]["current_status"] == "FAILURE"


DOORWAY = REPO / "missions" / "doorway_closing.yaml"
CONTROLLER_PARAMS = {
    "dwb": REPO / "params" / "nav2_params_dwb.yaml",
    "mppi": REPO / "params" / "nav2_params.yaml",
    "rpp": REPO / "params" / "nav2_params_rpp.yaml",
}


# Every controller: the mission's seed 0 for DWB and MPPI (~20 s a run), seeds 0-2 for RPP
# (~3 s); bench/doorway.py sweeps seeds 0-19 per controller (success, no contact, <= 90 s).
@pytest.mark.parametrize(
    ("controller", "seed"), [("dwb", 0), ("mppi", 0), ("rpp", 0), ("rpp", 1), ("rpp", 2)]
)
def test_a_doorway_closing_mid_run_is_replanned_around(tmp_path, controller, seed):
    # A door slides shut over the x = 4 doorway (y 3-4) about 4 s into the run; the map
    # does not know it, so only the lidar can tell the planner to go round by the top.
    # Once round, the door must stay in the global costmap while the robot walks away
    # from it (2.5-3 m: too far to mark, near enough to clear), or NavFn sends the
    # robot back and it dithers in the upper doorway.
    mission = Mission.load(
        DOORWAY, seed=seed, overrides={"mission.params": str(CONTROLLER_PARAMS[controller])}
    )
    out = tmp_path / "out"
    report = run_mission(mission, out)
    assert report.succeeded, report.error_msg
    assert report.contacts == [] and report.collisions == 0
    assert report.sim_time <= 90.0
    assert report.replans >= 1 and report.recoveries == 0
    rows = trajectory(out)
    through_top = [r for r in rows if 3.8 < r["gt_x"] < 4.2 and 6.0 < r["gt_y"] < 7.0]
    assert through_top, "the robot did not go round through the upper doorway"
    back = [r["t"] for r in rows if r["t"] > through_top[0]["t"] and r["gt_x"] < 3.7]
    assert not back, f"the robot went back into the left room at t = {back[0]:.1f} s"
    assert math.hypot(rows[-1]["gt_x"] - 6.0, rows[-1]["gt_y"] - 3.0) <= TOLERANCE


#: sha256 of trajectory.csv of `short_run` (seed 0, AMCL localising). Every closed-loop
#: computation is IEEE arithmetic in a fixed order (btnav.core.fmath, no SIMD-dispatched
#: numpy kernel, no BLAS, no libm sin/cos/atan2/exp/log), so any x86-64 machine gives these
#: bytes. If a change alters the trajectory on purpose, run this test, check the run
#: still looks right and paste the new digest.
SHORT_RUN_DIGEST = "c60dc5fb6ad852694118d2dbfdcbc4e98e6ec91c4244f73f6bca1e7d21931d94"


@pytest.fixture(scope="module")
def native_digest(tmp_path_factory, short_run_digest) -> str:
    """The short run's digest on this CPU as it is, once for the two tests below."""
    return short_run_digest(tmp_path_factory.mktemp("native"))


def test_a_short_runs_trajectory_is_pinned(native_digest):
    assert native_digest == SHORT_RUN_DIGEST, (
        "the short run's trajectory changed: if on purpose, "
        f"set SHORT_RUN_DIGEST = {native_digest!r}"
    )


@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64"), reason="x86-64 SIMD levels")
def test_the_trajectory_does_not_depend_on_the_cpus_simd_or_fma_level(
    tmp_path, native_digest, short_run_digest
):
    # numpy dispatches its kernels on the CPU's SIMD level at run time, and glibc picks an
    # FMA or a non-FMA variant of sin, cos, atan2, exp and log (Python's math module) by
    # CPU; with AVX2 and FMA switched off for either, it runs as on an older CPU. The
    # trajectory must not notice.
    native = native_digest
    assert short_run_digest(tmp_path / "numpy", NPY_DISABLE_CPU_FEATURES="X86_V3") == native
    assert (
        short_run_digest(tmp_path / "glibc", GLIBC_TUNABLES="glibc.cpu.hwcaps=-AVX2,-FMA") == native
    )


def test_the_same_seed_gives_the_same_run_bit_for_bit(tmp_path):
    path = write_mission(tmp_path, "short", task={"navigate_to_pose": [3.0, 2.0, 1.57]})
    outs = [tmp_path / "a", tmp_path / "b", tmp_path / "c"]
    run_mission(Mission.load(path), outs[0])
    run_mission(Mission.load(path), outs[1])
    run_mission(Mission.load(path, seed=1), outs[2])
    for name in ("trajectory.csv", "bt_log.jsonl"):
        assert (outs[0] / name).read_bytes() == (outs[1] / name).read_bytes()
    a, b = read_report(outs[0]), read_report(outs[1])
    assert {k: v for k, v in a.items() if k != "wall_time"} == {
        k: v for k, v in b.items() if k != "wall_time"
    }
    other = trajectory(outs[2])
    assert [r["odom_x"] for r in other] != [r["odom_x"] for r in trajectory(outs[0])]


def test_a_time_limit_cancels_the_task(tmp_path):
    out = tmp_path / "out"
    code = main(["run", str(TOUR), "--out", str(out), "--set", "mission.time_limit=3"])
    assert code == 1
    report = read_report(out)
    assert report["status"] == "canceled" and "time_limit" in report["error_msg"]
    assert 3.0 <= report["sim_time"] < 4.0
    assert trajectory(out)[-1]["cmd_v"] == 0.0  # canceled means stopped


def test_navigator_from_mission_is_the_python_api(tmp_path):
    assert btnav.Navigator is btnav.mission.Navigator
    nav = btnav.Navigator.from_mission(TOUR, seed=2)
    assert nav.mission.seed == 2 and nav.now == 0.0
    assert nav.go_to_pose((3.0, 2.0, 1.57))
    result = nav.wait_until_done(60)
    assert result is not None and result.succeeded
    assert math.hypot(nav.robot_pose.x - 3.0, nav.robot_pose.y - 2.0) <= TOLERANCE


@pytest.mark.parametrize("seed", [0, 1])
def test_navigate_through_poses_passes_each_pose_in_one_goal(tmp_path, seed):
    poses = [[3.0, 2.0, 1.57], [6.0, 3.0, 0.0]]
    path = write_mission(tmp_path, "through", task={"navigate_through_poses": poses}, seed=seed)
    out = tmp_path / "out"
    report = run_mission(Mission.load(path), out)
    assert report.succeeded and report.collisions == 0 and report.goals == 2
    rows = trajectory(out)
    for x, y, _ in poses:
        assert min(math.hypot(r["gt_x"] - x, r["gt_y"] - y) for r in rows) <= TOLERANCE
    log = bt_log(out)
    assert {e["navigator"] for e in log} == {"navigate_through_poses"}
    assert any(e["node_name"].endswith("ComputePathThroughPoses") for e in log)


def test_nav2s_bounds_check_tree_runs_and_stops_a_robot_off_its_path(tmp_path, nav2_dir):
    xml = (nav2_dir / "behavior_trees" / "navigate_to_pose_w_bounds_check.xml").read_text()
    ok = write_mission(
        tmp_path,
        "bounds",
        tree=str(nav2_dir / "behavior_trees" / "navigate_to_pose_w_bounds_check.xml"),
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
    )
    assert run_mission(Mission.load(ok), tmp_path / "ok").succeeded  # within 0.2 m all along
    tight = tmp_path / "tight.xml"
    tight.write_text(
        xml.replace(
            'max_error_left="0.2" max_error_right="0.2"',
            'max_error_left="0.002" max_error_right="0.002"',
        )
    )
    path = write_mission(
        tmp_path, "tight", tree=str(tight), task={"navigate_to_pose": [3.0, 2.0, 1.57]}
    )
    report = run_mission(Mission.load(path), tmp_path / "tight")
    assert report.status == "failed" and report.sim_time < 5.0
    log = bt_log(tmp_path / "tight")
    assert any(
        e["type"] == "IsWithinPathTrackingBounds" and e["current_status"] == "FAILURE" for e in log
    )
