"""The sources: a scan's readings as base-frame points (range test, mount, the robot's
motion since the scan), timeouts, polygons sampled along their edges, costmap cells, and
exclusion zones."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.collision_monitor import (
    CostmapSource,
    ExclusionZone,
    PolygonInstance,
    PolygonSource,
    ScanSource,
    SourceFrames,
    make_sources,
)
from btnav.collision_monitor.decide import collect_points
from btnav.core.errors import ParamsError
from btnav.core.frames import BASE_FOOTPRINT, BASE_LINK, ODOM, FrameTree
from btnav.core.geometry import Pose2D
from btnav.core.messages import LaserScan
from btnav.costmap.costmap_2d import Costmap2D
from btnav.params.collision_monitor import ExclusionZone as ZoneParams
from btnav.params.collision_monitor import ObservationSource

from .zones import POLYGON_STOP, monitor_params


def tree(robot: Pose2D | None = None) -> FrameTree:
    t = FrameTree.rep105()
    t.set_transform(ODOM, BASE_FOOTPRINT, robot or Pose2D(), stamp=0.0)
    t.set_static(BASE_LINK, "laser", Pose2D(0.1, 0.0, 0.0))
    return t


def scan(ranges: list[float], stamp: float = 0.0, angle_min: float = 0.0) -> LaserScan:
    return LaserScan(
        stamp=stamp,
        frame_id="laser",
        angle_min=angle_min,
        angle_max=angle_min + (len(ranges) - 1) * math.pi / 2,
        angle_increment=math.pi / 2,
        range_min=0.12,
        range_max=8.0,
        ranges=np.array(ranges, np.float32),
    )


def scan_source(frames: SourceFrames, **params: object) -> ScanSource:
    return ScanSource("scan", ObservationSource.model_validate(params), frames, 2.0)


def test_scan_readings_in_range_become_base_frame_points() -> None:
    src = scan_source(SourceFrames(tree()))
    # ahead 1 m, left too close (-inf), behind nothing hit (+inf), right NaN; then 9 m > max
    src.receive(scan([1.0, -np.inf, np.inf, np.nan]))
    np.testing.assert_allclose(src.get_data(0.0), [[1.1, 0.0]])  # 0.1 m mount ahead
    src.receive(scan([0.12, 8.0, 8.01, 0.11]))
    np.testing.assert_allclose(src.get_data(0.0), [[0.22, 0.0], [0.1, 8.0]], atol=1e-6)


def test_scan_ignores_pointcloud_height_keys_as_nav2_does() -> None:
    # nav2_params.yaml writes min_height 0.15 for its scan: a pointcloud key, unread by Scan
    src = scan_source(SourceFrames(tree()), min_height=0.15, max_height=2.0, min_range=0.5)
    src.receive(scan([0.3]))
    assert len(src.get_data(0.0)) == 1


def test_base_shift_correction_moves_points_by_the_motion_since_the_scan() -> None:
    t = tree(Pose2D(2.0, 1.0, 0.0))
    corrected = scan_source(SourceFrames(t))
    uncorrected = scan_source(SourceFrames(t, base_shift_correction=False))
    for src in (corrected, uncorrected):
        src.receive(scan([1.0]))  # an obstacle 1.1 m ahead of the robot at (2, 1)
    # the robot then drives 0.3 m ahead and turns 90 degrees left
    t.set_transform(ODOM, BASE_FOOTPRINT, Pose2D(2.3, 1.0, math.pi / 2), stamp=0.1)
    np.testing.assert_allclose(corrected.get_data(0.1), [[0.0, -0.8]], atol=1e-12)
    np.testing.assert_allclose(uncorrected.get_data(0.1), [[1.1, 0.0]], atol=1e-12)


def test_source_timeout() -> None:
    src = scan_source(SourceFrames(tree()), source_timeout=0.5)
    assert src.get_data(0.0) is None  # nothing received yet
    src.receive(scan([1.0], stamp=1.0))
    assert src.get_data(1.5) is not None and src.get_data(1.51) is None
    never = scan_source(SourceFrames(tree()), source_timeout=0.0)  # 0: no timeout
    never.receive(scan([1.0], stamp=0.0))
    assert never.get_data(1e6) is not None


def test_collect_points_reports_invalid_sources_with_a_timeout_only() -> None:
    frames = SourceFrames(tree())
    fresh, silent, untimed = (
        scan_source(frames),
        scan_source(frames),
        scan_source(frames, source_timeout=0.0),
    )
    fresh.name, silent.name, untimed.name = "fresh", "silent", "untimed"
    fresh.receive(scan([1.0]))
    points, invalid = collect_points([fresh, untimed, silent], 0.0, stop_at_invalid=False)
    assert invalid == ["silent"] and len(points["fresh"]) == 1 and len(points["untimed"]) == 0


def test_polygon_source_samples_edges_replaces_by_id_and_drops_old_ones() -> None:
    frames = SourceFrames(tree())
    src = PolygonSource(
        "obj", ObservationSource(type="polygon", sampling_distance=0.1), frames, 1.0
    )
    assert src.get_data(0.0) is None  # nothing yet: invalid, as in Nav2
    square = [[1.0, 0.0], [1.2, 0.0], [1.2, 0.2], [1.0, 0.2]]
    src.receive(PolygonInstance(1, square, BASE_FOOTPRINT, stamp=0.0))
    pts = src.get_data(0.0)
    assert len(pts) == 4 * 3  # 2 intervals per 0.2 m edge, both ends: 3 points per edge
    assert points_set(pts) == {(1.0, 0.0), (1.1, 0.0), (1.2, 0.0), (1.2, 0.1), (1.2, 0.2),
                               (1.1, 0.2), (1.0, 0.2), (1.0, 0.1)}  # fmt: skip
    src.receive(PolygonInstance(1, [[p[0], p[1] + 1] for p in square], BASE_FOOTPRINT, 0.5))
    assert points_set(src.get_data(0.5)) == {(x, y + 1) for x, y in points_set(pts)}
    assert len(src.get_data(1.6)) == 0  # older than the 1 s timeout: dropped


def points_set(pts: np.ndarray) -> set[tuple[float, float]]:
    return {(round(float(x), 6), round(float(y), 6)) for x, y in pts}


def test_costmap_source_takes_cells_at_the_threshold_and_unknown() -> None:
    costs = np.zeros((4, 4), np.uint8)
    costs[0, 0], costs[1, 2], costs[3, 3], costs[2, 1] = 253, 254, 255, 252
    grid = Costmap2D(costs, 0.5, origin_x=-1.0, origin_y=-1.0, frame_id=ODOM)
    frames = SourceFrames(tree(Pose2D(0.0, 0.0, math.pi / 2)))

    def source(**p: object) -> CostmapSource:
        params = ObservationSource.model_validate({"type": "costmap", **p})
        return CostmapSource("cm", params, frames, 2.0, costmap=lambda: (grid, ODOM, 0.0))

    # cell (mx, my) centre: -1 + 0.5 (m + 0.5); the robot faces +y, so odom (x, y) is (y, -x)
    assert points_set(source().get_data(0.0)) == {(-0.75, 0.75), (-0.25, -0.25), (0.75, -0.75)}
    assert points_set(
        source(cost_threshold=254, treat_unknown_as_obstacle=False).get_data(0.0)
    ) == {(-0.25, -0.25)}
    stale = CostmapSource(
        "cm", ObservationSource(type="costmap"), frames, 2.0, costmap=lambda: (grid, ODOM, None)
    )
    assert stale.get_data(0.0) is None  # no update yet


def test_exclusion_zones_drop_points_in_them() -> None:
    t = tree()
    t.set_transform(ODOM, "dock", Pose2D(1.0, 0.0, 0.0), stamp=0.0)
    pts = np.array([[0.05, 0.0], [1.0, 0.05], [2.0, 0.0]])

    def zone(**p: object) -> ExclusionZone:
        return ExclusionZone(
            "z", ZoneParams.model_validate({"enabled": True, **p}), t, BASE_FOOTPRINT, ODOM
        )

    body = zone(type="circle", radius=0.1)  # rides with the robot
    np.testing.assert_array_equal(body.apply(0.0, pts), pts[1:])
    dock = zone(frame_id="dock", points="[[-0.2, -0.2], [0.2, -0.2], [0.2, 0.2], [-0.2, 0.2]]")
    np.testing.assert_array_equal(dock.apply(0.0, pts), pts[[0, 2]])
    # a dock frame not seen for longer than the hold window excludes nothing (fail safe)
    assert len(dock.apply(0.5, pts)) == 3
    held = zone(frame_id="dock", frame_hold_timeout=1.0, type="circle", radius=0.2)
    assert len(held.apply(0.5, pts)) == 2
    assert len(zone(frame_id="nowhere", type="circle", radius=5.0).apply(0.0, pts)) == 3
    assert len(zone(type="circle", radius=5.0, min_height=0.1).apply(0.0, pts)) == 3
    off = ExclusionZone("z", ZoneParams(type="circle", radius=5.0), t, BASE_FOOTPRINT, ODOM)
    assert len(off.apply(0.0, pts)) == 3  # disabled by default, as in Nav2


def test_a_source_applies_its_exclusion_zones() -> None:
    model = monitor_params(
        {"PolygonStop": POLYGON_STOP},
        {"scan": {"type": "scan", "exclusion_zones": ["bumper"]}},
        bumper={"enabled": True, "type": "circle", "radius": 0.5},
    )
    (src,) = make_sources(model, tree())
    assert isinstance(src, ScanSource)
    src.receive(scan([0.3, 2.0]))
    np.testing.assert_allclose(src.get_data(0.0), [[0.1, 2.0]], atol=1e-6)


@pytest.mark.parametrize("kind", ["pointcloud", "range"])
def test_sensors_a_2d_simulation_lacks_are_refused(kind: str) -> None:
    model = monitor_params({"PolygonStop": POLYGON_STOP}, {"cam": {"type": kind}})
    with pytest.raises(ParamsError, match="lidars only"):
        make_sources(model, tree())


def test_a_scan_of_other_beams_is_read_with_its_own_angles() -> None:
    # the beams' directions are kept between scans: a scan whose beams start elsewhere (or
    # are more) must not be read with the previous scan's
    src = scan_source(SourceFrames(tree()))
    src.receive(scan([1.0, 1.0]))
    np.testing.assert_allclose(src.get_data(0.0), [[1.1, 0.0], [0.1, 1.0]], atol=1e-12)
    src.receive(scan([1.0, 1.0], angle_min=math.pi / 2))
    np.testing.assert_allclose(src.get_data(0.0), [[0.1, 1.0], [-0.9, 0.0]], atol=1e-12)
    src.receive(scan([1.0, 1.0, 2.0], angle_min=math.pi / 2))
    np.testing.assert_allclose(
        src.get_data(0.0), [[0.1, 1.0], [-0.9, 0.0], [0.1, -2.0]], atol=1e-12
    )
