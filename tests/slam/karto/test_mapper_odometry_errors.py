"""slam_toolbox's engine on odometry that is wrong by more than its sequential window.

FR079's wheel odometry counts reversing as driving forward: between two processed
scans 0.5 m apart the odometry's guess is then 1 m from the truth, and the sequential
matcher searches only +-0.25 m around it. The mapper must still place the scans where
the laser says they were.
"""

from __future__ import annotations

import numpy as np
import pytest

from btnav.params.localization import SlamToolboxParams
from btnav.slam.karto import mapper as mapper_module
from btnav.slam.karto.mapper import Mapper
from btnav.slam.karto.offline import run_slam
from btnav.slam.logs import RecordedLog

from .test_scan_matcher import RANGE_MAX, ROOM, cast_ranges, laser_scan

SPEED = 0.5  # m/s
RATE = 10.0  # scans per second


def reversing_log() -> tuple[RecordedLog, np.ndarray]:
    """A robot drives 2.6 m along the room, then backs 2.2 m the way it came (heading
    0 throughout); its odometry counts the reversal as forward travel (|v|)."""
    step = SPEED / RATE
    out = np.arange(0.0, 2.6, step)
    back = 2.6 - np.arange(0.0, 2.2 + 1e-9, step)
    x = 1.2 + np.concatenate([out, back])
    n = len(x)
    truth = np.column_stack([x, np.full(n, 2.0), np.zeros(n)])
    odom = truth.copy()
    odom[:, 0] = 1.2 + step * np.arange(n)  # |v|: always forward
    stamps = np.arange(n) / RATE
    scans = [laser_scan(t, cast_ranges(ROOM, tuple(p))) for t, p in zip(stamps, truth, strict=True)]
    return RecordedLog("reversing", scans, stamps, odom, duration=float(stamps[-1])), truth


def node_errors(log: RecordedLog, truth: np.ndarray) -> tuple[np.ndarray, Mapper]:
    """Each processed scan's distance from the truth, and the mapper that placed them."""
    result = run_slam(log, SlamToolboxParams(max_laser_range=RANGE_MAX), trajectory="odometry")
    stamps = np.array([s.stamp for s in log.scans])
    at = np.searchsorted(stamps, [s.stamp for s in result.mapper.scans])
    d = result.mapper.poses[:, :2] - truth[at, :2]
    return np.hypot(d[:, 0], d[:, 1]), result.mapper


def test_reversing_with_forward_odometry_keeps_the_processed_scans_in_place():
    log, truth = reversing_log()
    errors, _ = node_errors(log, truth)
    assert len(errors) >= 9
    assert errors.max() < 0.05, errors


def test_without_the_wider_search_the_same_drive_tears_the_map(monkeypatch):
    """The mechanism above is what holds it: Karto's sequential match alone ends up
    far from the truth on the way back."""
    monkeypatch.setattr(mapper_module, "RESCUE_BELOW_RESPONSE", -1.0)
    log, truth = reversing_log()
    assert node_errors(log, truth)[0].max() > 0.3


@pytest.mark.parametrize("below", [mapper_module.RESCUE_BELOW_RESPONSE, -1.0])
def test_a_well_supported_drive_never_needs_the_wider_search(below, monkeypatch):
    """Odometry that is right: every sequential match is good and none is replaced,
    whether or not the wider search is enabled (same poses bit for bit)."""
    monkeypatch.setattr(mapper_module, "RESCUE_BELOW_RESPONSE", below)
    log, truth = reversing_log()
    log = RecordedLog("true odometry", log.scans, log.odom_stamps, truth, duration=log.duration)
    result = run_slam(log, SlamToolboxParams(max_laser_range=RANGE_MAX), trajectory="odometry")
    assert result.mapper.rescues == 0
    stamps = np.array([s.stamp for s in log.scans])
    at = np.searchsorted(stamps, [s.stamp for s in result.mapper.scans])
    d = result.mapper.poses[:, :2] - truth[at, :2]
    assert np.hypot(d[:, 0], d[:, 1]).max() < 0.02
