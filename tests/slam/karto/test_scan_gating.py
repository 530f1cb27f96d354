"""Which scans reach the graph: slam_toolbox's shouldProcessScan, Karto's HasMovedEnough,
and the running buffer the next scan is matched against, each key doing what it says."""

from __future__ import annotations

import math

import numpy as np

from btnav.params.localization import SlamToolboxParams
from btnav.slam.karto.mapper import Mapper
from btnav.slam.karto.scan_gate import ScanGate

from ..loop_drive import drive_loop
from .test_scan_matcher import BEAMS, box, cast_ranges, polyline

ROOM = np.vstack(
    [
        polyline((0, 0), (10, 0), (10, 8), (0, 8), (0, 0)),
        box(7.5, 2.0, 1.0, 0.6),
        box(2.0, 6.0, 0.6, 1.0),
    ]
)
ANGLES = np.linspace(-math.pi, math.pi, 8, endpoint=False)


def params(**keys: object) -> SlamToolboxParams:
    return SlamToolboxParams(**keys)


def passed(gate: ScanGate, stamps: np.ndarray, xs: np.ndarray) -> list[int]:
    """The 1-based numbers of the scans the gate lets through."""
    return [
        i + 1 for i, (t, x) in enumerate(zip(stamps, xs, strict=True)) if gate(t, (x, 0.0, 0.0))
    ]


def test_throttle_scans_passes_every_nth_scan_after_the_first_five():
    gate = ScanGate(
        params(throttle_scans=3, minimum_time_interval=0.0, minimum_travel_distance=0.5)
    )
    n = 20
    assert passed(gate, np.arange(n, dtype=float), np.arange(n, dtype=float)) == [
        1,
        6,
        9,
        12,
        15,
        18,
    ]


def test_minimum_time_interval_holds_back_scans_that_come_too_soon():
    gate = ScanGate(
        params(throttle_scans=1, minimum_time_interval=1.0, minimum_travel_distance=0.1)
    )
    stamps = np.arange(16) * 0.25  # four scans a second, each a metre on
    assert passed(gate, stamps, np.arange(16, dtype=float)) == [1, 5, 9, 13]


def test_minimum_travel_distance_allows_slam_toolbox_s_ten_percent_and_not_turning():
    p = params(throttle_scans=1, minimum_time_interval=0.0, minimum_travel_distance=1.0)
    gate = ScanGate(p)
    for t in range(5):  # the first scan passes; the next four never do
        gate(float(t), (0.0, 0.0, 0.0))
    assert not gate(5.0, (0.0, 0.0, 3.0))  # turning alone
    assert not gate(6.0, (0.89, 0.0, 0.0))  # under sqrt(0.8) m
    assert gate(7.0, (0.9, 0.0, 0.0))


def _mapper(**keys: object) -> Mapper:
    return Mapper(params(use_scan_matching=False, **keys))


def _process(mapper: Mapper, stamp: float, pose: tuple[float, float, float]) -> bool:
    points = np.column_stack([np.cos(ANGLES), np.sin(ANGLES)]) * 2.0
    ranges = np.full(len(ANGLES), 2.0, np.float32)
    return mapper.process(stamp, pose, points, ranges, ANGLES)


def test_karto_takes_a_scan_that_turned_or_moved_or_waited_enough():
    mapper = _mapper(
        minimum_time_interval=10.0, minimum_travel_distance=0.5, minimum_travel_heading=0.5
    )
    assert _process(mapper, 0.0, (0.0, 0.0, 0.0))
    assert not _process(mapper, 1.0, (0.2, 0.0, 0.4))  # too little of each
    assert _process(mapper, 2.0, (0.2, 0.0, 0.55))  # turned enough
    assert _process(mapper, 3.0, (0.75, 0.0, 0.55))  # moved enough
    assert not _process(mapper, 4.0, (0.8, 0.0, 0.55))
    assert _process(mapper, 13.0, (0.8, 0.0, 0.55))  # waited enough
    assert len(mapper.scans) == 4


def test_the_running_buffer_is_capped_by_count_and_by_span():
    """Karto's AddRunningScan: the scans the next one is matched against, at most
    `scan_buffer_size` of them, spanning at most `scan_buffer_maximum_scan_distance`."""
    by_count = Mapper(params(scan_buffer_size=5, scan_buffer_maximum_scan_distance=100.0))
    by_span = Mapper(params(scan_buffer_size=50, scan_buffer_maximum_scan_distance=1.0))
    angles = np.linspace(-math.pi, math.pi, BEAMS, endpoint=False)
    for mapper in (by_count, by_span):
        for i in range(12):
            pose = (2.0 + 0.3 * i, 3.0, 0.0)
            ranges = cast_ranges(ROOM, pose)
            ok = np.isfinite(ranges)
            points = np.column_stack([np.cos(angles), np.sin(angles)])[ok] * ranges[ok, None]
            assert mapper.process(float(i), pose, points, ranges.astype(np.float32), angles)
    assert by_count.running == list(range(7, 12))
    assert by_span.running == [8, 9, 10, 11]  # 0.9 m from first to last; 1.2 m is over


def test_the_map_is_published_every_map_update_interval_from_map_start_pose():
    """A 12 s drive: a map at the first scan, then one every `map_update_interval` of sim
    time; the graph's first node (the map frame's anchor) at `map_start_pose`."""
    p = params(map_update_interval=4.0, map_start_pose=[5.0, -2.0, 1.0])
    published: list[float] = []
    drive = drive_loop(
        params=p,
        route=[(1.2, 1.2), (6.0, 1.2)],
        on_start=lambda slam: slam.subscribe_map(
            lambda _: published.append(slam.context.clock.now)
        ),
    )
    assert len(published) >= 3
    assert published[0] < 1.0
    np.testing.assert_allclose(np.diff(published), 4.0, atol=0.06)  # SLAM runs at 20 Hz
    np.testing.assert_allclose(drive.slam.mapper.poses[0], [5.0, -2.0, 1.0], atol=0.01)
