"""The collision monitor on the command path of the small office's robot, and the detector
beside it: a box dropped in front of the robot driving at full speed, a slowdown zone, the
monitor switched off (by its params and by the ToggleCollisionMonitor tree node), and the
detector reporting without touching the command.

The robot (radius 0.22 m, 0.5 m/s, 1 m/s^2) is driven straight ahead by a stand-in
controller sending `cmd_vel_nav` at 20 Hz; the monitor takes those commands
(`runtime.route_cmd_vel`) and commands the base.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from btnav.bt import load_tree
from btnav.collision_monitor import ActionType
from btnav.core.errors import ParamsError
from btnav.core.messages import Twist
from btnav.nav.collision_monitor_server import CollisionDetectorServer, CollisionMonitorServer
from btnav.nav.runtime import Runtime, Stage

from ..collision_monitor.zones import POLYGON_SLOW, POLYGON_STOP
from .navstack_helpers import PARAMS, office

#: The robot's size and top speed (worlds/small_office.yaml).
RADIUS, V_MAX = 0.22, 0.5
#: A box 0.3 m deep and 0.6 m wide, dropped this far (centre) ahead of the robot.
BOX, DROP_AHEAD = (0.3, 0.6), 1.0


class Driver:
    """A stand-in controller: full speed ahead, as `cmd_vel_nav` at 20 Hz."""

    rate = 20.0

    def __init__(self, runtime: Runtime, speed: float = V_MAX) -> None:
        self.runtime, self.speed = runtime, speed

    def update(self, now: float) -> None:
        self.runtime.set_cmd_vel(Twist(self.speed, 0.0, 0.0))


class Speeds:
    """The robot's ground-truth x and forward speed at every step."""

    rate = 1000.0
    stage = Stage.MONITOR

    def __init__(self, runtime: Runtime) -> None:
        self.world = runtime.world
        self.samples: list[tuple[float, float]] = []

    def update(self, now: float) -> None:
        self.samples.append((self.world.robot_pose.x, self.world.robot_twist.linear_x))


def params_file(tmp_path: Path, section: dict[str, Any] | None = None, **keys: Any) -> Path:
    """Nav2's params with the collision_monitor section as Nav2 ships it, or with its
    zones replaced by `section` (name -> zone), and its top-level keys changed by `keys`."""
    doc = yaml.safe_load(PARAMS.read_text())
    cm = doc["collision_monitor"]["ros__parameters"]
    if section is not None:
        del cm[cm["polygons"][0]]
        cm["polygons"] = list(section)
        cm.update(section)
    cm.update(keys)
    out = tmp_path / "nav2_params.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def monitored(params: Path) -> tuple[Any, Runtime, CollisionMonitorServer, Speeds]:
    world, rt, stack = office(params=params)
    monitor = CollisionMonitorServer(
        rt, stack.params.server("collision_monitor"), stack.local_costmap
    )
    rt.route_cmd_vel(monitor.command_received)
    rt.add(Driver(rt))
    speeds = rt.add(Speeds(rt))
    return world, rt, monitor, speeds


def drop_box_ahead(world: Any, rt: Runtime) -> float:
    """At full speed after 1 s, a box appears ahead; returns the x of its near face."""
    rt.spin_for(1.0)
    assert world.robot_twist.linear_x == pytest.approx(V_MAX)
    x = world.robot_pose.x + DROP_AHEAD
    world.add_box((x, world.robot_pose.y), BOX)
    return x - BOX[0] / 2


def stop_zone(front: float) -> dict[str, Any]:
    """Nav2's PolygonStop with its front edge at `front` m."""
    points = f"[[{front}, 0.3], [{front}, -0.3], [0.0, -0.3], [0.0, 0.3]]"
    return {"PolygonStop": {**POLYGON_STOP, "points": points}}


def test_box_dropped_ahead_stop_polygon_halts_the_robot_short_of_it(tmp_path: Path) -> None:
    # Nav2's PolygonStop ends 0.3 m ahead: 8 cm past this robot's front, less than its
    # 12.5 cm braking distance at 0.5 m/s; 0.5 m leaves room for that and a scan's age
    world, rt, monitor, speeds = monitored(params_file(tmp_path, stop_zone(0.5)))
    face = drop_box_ahead(world, rt)
    rt.spin_for(3.0)
    gap = face - (world.robot_pose.x + RADIUS)
    assert world.contacts == []
    assert 0.05 < gap < 0.3
    assert speeds.samples[-1][1] == 0.0 and rt.cmd_vel == Twist()
    assert monitor.action.action_type == ActionType.STOP
    assert monitor.action.polygon_name == "PolygonStop"
    assert monitor.count(ActionType.STOP) == 1


def test_nav2s_polygon_stop_is_too_short_for_this_robot_at_full_speed(tmp_path: Path) -> None:
    """What sizing the stop zone means: Nav2's 0.3 m zone is reached too late to brake."""
    world, rt, monitor, _ = monitored(params_file(tmp_path, stop_zone(0.3)))
    drop_box_ahead(world, rt)
    rt.spin_for(3.0)
    assert monitor.count(ActionType.STOP) == 1 and len(world.contacts) == 1


def test_box_dropped_ahead_nav2s_footprint_approach_halts_the_robot_short_of_it(
    tmp_path: Path,
) -> None:
    # nav2_params.yaml's collision_monitor as Nav2 ships it: FootprintApproach, 1.2 s
    world, rt, monitor, speeds = monitored(params_file(tmp_path))
    face = drop_box_ahead(world, rt)
    rt.spin_for(6.0)
    gap = face - (world.robot_pose.x + RADIUS)
    assert world.contacts == []
    assert 0.0 < gap < 0.1
    assert speeds.samples[-1][1] == 0.0
    assert monitor.action.polygon_name == "FootprintApproach"
    assert monitor.action.action_type == ActionType.APPROACH
    # it slowed down gradually, not at once: the speed passed through the middle values
    mid = [v for _, v in speeds.samples if 0.1 < v < 0.4]
    assert len(mid) > 50


def test_the_robot_slows_in_a_slowdown_zone(tmp_path: Path) -> None:
    # Nav2's PolygonSlow (0.4 m around the robot, ratio 0.3) and a cabinet beside the way,
    # its side 0.35 m from the robot's path: in the zone, clear of the robot
    world, rt, monitor, speeds = monitored(params_file(tmp_path, {"PolygonSlow": POLYGON_SLOW}))
    world.add_box((1.8, 1.0 + 0.35 + 0.1), (0.4, 0.2))
    rt.spin_for(9.5)
    assert world.contacts == []
    passing = [v for x, v in speeds.samples if 1.8 - 0.2 <= x <= 1.8 + 0.2]
    assert passing and max(passing) == pytest.approx(V_MAX * 0.3)
    assert speeds.samples[-1][1] == pytest.approx(V_MAX)  # past it: full speed again
    assert monitor.count(ActionType.SLOWDOWN) == 1
    kinds = [s.action_type for s in monitor.states]
    assert kinds[-2:] == [ActionType.SLOWDOWN, ActionType.DO_NOTHING]


def test_disabled_monitor_passes_every_command_unchanged(tmp_path: Path) -> None:
    world, rt, monitor, _ = monitored(params_file(tmp_path, stop_zone(0.5), enabled=False))
    sent: list[Twist] = []
    monitor.publish = lambda cmd: (sent.append(cmd), rt.command_base(cmd))  # type: ignore[func-returns-value]
    drop_box_ahead(world, rt)
    rt.spin_for(3.0)
    assert sent and all(cmd == Twist(V_MAX, 0.0, 0.0) for cmd in sent)
    assert len(world.contacts) == 1  # nothing stopped it
    assert monitor.states == [] and monitor.count(ActionType.STOP) == 0


def test_stop_pub_timeout_then_silence(tmp_path: Path) -> None:
    # a box right ahead from the start: stop at once, zeros for stop_pub_timeout (2 s in
    # nav2_params.yaml), then nothing until the command may move the robot again
    world, rt, monitor, _ = monitored(params_file(tmp_path, stop_zone(0.5)))
    world.add_box((1.0 + 0.4, 1.0), BOX)
    rt.spin_for(1.0)
    published_at_1s = monitor.published
    rt.spin_for(3.0)
    assert monitor.received == 80
    # 20 Hz: the first command passes (the start's scan predates the box), the stop at
    # 0.1 s and 2 s of zeros after it are 41 more; the other 38 are held back
    assert monitor.published == 1 + 41 and published_at_1s == 20
    assert world.robot_twist.linear_x == 0.0 and world.contacts == []


def test_toggle_collision_monitor_tree_node_switches_it(tmp_path: Path) -> None:
    _world, rt, stack = office(params=params_file(tmp_path, stop_zone(0.5)))
    monitor = CollisionMonitorServer(
        rt, stack.params.server("collision_monitor"), stack.local_costmap
    )

    class Stack:  # the stack's services with the monitor's (NavStack.services() adds them)
        def services(self) -> dict[str, Any]:
            return {**stack.services(), **monitor.services()}

    def run(enable: str, name: str = "collision_monitor/toggle") -> Any:
        xml = (
            '<root BTCPP_format="4" main_tree_to_execute="T"><BehaviorTree ID="T">'
            f'<ToggleCollisionMonitor enable="{enable}" service_name="{name}"/>'
            "</BehaviorTree></root>"
        )
        tree = load_tree(xml, clock=rt.clock, context={"runtime": rt, "stack": Stack()})
        tree.tick_once()
        return tree.status

    assert monitor.enabled
    assert run("false").name == "SUCCESS" and not monitor.enabled
    assert run("true", "/collision_monitor/toggle").name == "SUCCESS" and monitor.enabled
    assert monitor.toggle(False).message == "Collision monitor toggled off successfully"


def test_a_pointcloud_source_is_refused_where_it_is_written(tmp_path: Path) -> None:
    camera = {"type": "pointcloud", "topic": "/intel_realsense_r200_depth/points"}
    path = params_file(
        tmp_path, stop_zone(0.5), observation_sources=["scan", "pointcloud"], pointcloud=camera
    )
    with pytest.raises(ParamsError) as info:
        office(params=path)  # the stack brings the monitor up, and refuses the source
    err = info.value
    assert err.key == "collision_monitor.pointcloud.type" and err.file == str(path)
    assert path.read_text().splitlines()[err.line - 1].strip() == "type: pointcloud"


def detector_params(tmp_path: Path) -> Path:
    """Nav2's params plus collision_detector_params.yaml's section (nav2_collision_monitor),
    without the collision monitor (nothing on the command chain acts)."""
    doc = yaml.safe_load(PARAMS.read_text())
    del doc["collision_monitor"]
    doc["collision_detector"] = {
        "ros__parameters": {
            "frequency": 10.0,
            "base_frame_id": "base_footprint",
            "odom_frame_id": "odom",
            "transform_tolerance": 0.5,
            "source_timeout": 5.0,
            "base_shift_correction": True,
            "polygons": ["PolygonFront"],
            "PolygonFront": {
                "type": "polygon",
                "points": "[[0.3, 0.3], [0.3, -0.3], [0.0, -0.3], [0.0, 0.3]]",
                "action_type": "none",
                "min_points": 4,
                "visualize": True,
                "polygon_pub_topic": "polygon_front",
                "enabled": True,
            },
            "observation_sources": ["scan"],
            "scan": {"type": "scan", "topic": "scan", "enabled": True},
        }
    }
    out = tmp_path / "nav2_params.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def test_collision_detector_reports_and_leaves_the_command_alone(tmp_path: Path) -> None:
    world, rt, stack = office(params=detector_params(tmp_path))
    states: list[Any] = []
    detector = stack.servers["collision_detector"]  # the stack brings it up beside the chain
    assert isinstance(detector, CollisionDetectorServer) and detector.rate == 10.0
    detector.publish = states.append
    rt.add(Driver(rt, speed=0.2))
    rt.spin_for(1.0)
    assert len(states) == 10 and not any(s.detected("PolygonFront") for s in states)
    world.add_box((world.robot_pose.x + 0.5, world.robot_pose.y), BOX)
    rt.spin_for(1.5)
    assert detector.state.polygons == ("PolygonFront",) and detector.state.detected("PolygonFront")
    assert rt.cmd_vel == Twist(0.2, 0.0, 0.0)  # it never commands the base
    assert len(world.contacts) == 1  # and nothing else stopped the robot


def test_collision_detector_refuses_an_acting_polygon(tmp_path: Path) -> None:
    doc = yaml.safe_load(detector_params(tmp_path).read_text())
    doc["collision_detector"]["ros__parameters"]["PolygonFront"]["action_type"] = "stop"
    path = tmp_path / "acting.yaml"
    path.write_text(yaml.safe_dump(doc))
    with pytest.raises(ParamsError, match='must be "none"'):
        office(params=path)


def test_new_params_keep_the_scan_the_sources_had(tmp_path: Path) -> None:
    _world, rt, monitor, _speeds = monitored(params_file(tmp_path, stop_zone(0.5)))
    rt.spin_for(0.3)
    before = monitor.source("scan").source_data(rt.now)
    assert before is not None and len(before) > 100
    monitor.set_parameters(monitor.params)  # zones and sources rebuilt, as a live update does
    after = monitor.source("scan").source_data(rt.now)
    assert after is not None and np.array_equal(after, before)
