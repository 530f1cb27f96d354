"""A well-supported match takes the odometry's position along the direction it leaves
open (a corridor's length), where the odometry is clearly surer there.

Down a bare corridor every scan fits the running scans about as well anywhere along it:
Karto's response is flat there up to noise and its covariance says so (tens of cm along
the corridor, a few across), and Karto takes the best pose all the same. The corridor
loop's map slid 18 cm that way at seed 9 (tests/slam/karto/test_slam_loop.py). The odometry
here turns about a degree wrong every half metre, as the loop's does (too poor for the
three-dimensional fusion of poorly supported matches), but measures the travel well; the
mapper learns that from the good matches in the first stretch, among cabinets, and
holds the scans' places along the bare stretch after it.
"""

from __future__ import annotations

import math

import numpy as np

from btnav.core.geometry import compose_arrays, relative_arrays
from btnav.params.localization import SlamToolboxParams
from btnav.slam.karto.mapper import Mapper
from btnav.slam.karto.odometry_fusion import OdometryFusion
from btnav.slam.karto.offline import run_slam
from btnav.slam.karto.scan_matcher import MatchResult
from btnav.slam.logs import RecordedLog

from .test_scan_matcher import BEAMS, RANGE_MAX, box, cast_ranges, laser_scan, polyline

SPEED = 0.5  # m/s
RATE = 10.0  # scans per second
#: a 2.4 m corridor along x (off the grid's cells: a synthetic world on whole
#: centimetres rounds every point alike), cabinets along its first 15 m
MIDDLE = 0.037
CABINETS = [
    box(x, MIDDLE + (0.95 if k % 2 else -0.95), 0.6, 0.5)
    for k, x in enumerate(np.arange(-11.0, 4.0, 2.3))
]
WORLD = np.vstack(
    [
        polyline((-40, MIDDLE - 1.2), (40, MIDDLE - 1.2)),
        polyline((-40, MIDDLE + 1.2), (40, MIDDLE + 1.2)),
        *CABINETS,
    ]
)
#: where no cabinet is within the lidar's range any more (the last at x 3.95, 8 m range)
BARE_FROM = 12.0
#: the odometry's heading error per scan (rad): about a degree per processed scan
HEADING_NOISE = math.radians(0.3)


def corridor_log(seed: int = 0) -> tuple[RecordedLog, np.ndarray]:
    """36 m down the corridor at 0.5 m/s, 1 cm range noise; the odometry's travel exact,
    each scan's turn off by a normal error of `HEADING_NOISE` (seeded)."""
    x = -10.013 + np.arange(0.0, 36.0, SPEED / RATE)
    n = len(x)
    truth = np.column_stack([x, np.full(n, MIDDLE + 0.011), np.zeros(n)])
    stamps = np.arange(n) / RATE
    rng = np.random.default_rng(seed)
    scans = [
        laser_scan(t, cast_ranges(WORLD, tuple(p)) + rng.normal(0.0, 0.01, BEAMS))
        for t, p in zip(stamps, truth, strict=True)
    ]
    steps = relative_arrays(truth[:-1], truth[1:])
    steps[:, 2] += rng.normal(0.0, HEADING_NOISE, n - 1)
    odom = truth.copy()
    for k, step in enumerate(steps):
        odom[k + 1] = compose_arrays(odom[k], step[None, :])[0]
    return RecordedLog("corridor", scans, stamps, odom, duration=float(stamps[-1])), truth


def slide_along_the_bare_stretch() -> tuple[float, Mapper]:
    """How far the processed scans' error along the corridor moves over its bare
    stretch (m, the largest change from the first bare scan), and the mapper."""
    log, truth = corridor_log()
    result = run_slam(log, SlamToolboxParams(max_laser_range=RANGE_MAX), trajectory="odometry")
    mapper = result.mapper
    stamps = np.array([s.stamp for s in log.scans])
    at = np.searchsorted(stamps, [s.stamp for s in mapper.scans])
    along = mapper.poses[:, 0] - truth[at, 0]
    bare = truth[at, 0] > BARE_FROM
    assert bare.sum() >= 25
    return float(np.abs(along[bare] - along[np.argmax(bare)]).max()), mapper


def test_the_map_holds_its_place_along_a_bare_corridor():
    slide, mapper = slide_along_the_bare_stretch()
    assert mapper.odometry_noise.trusted
    assert mapper.fusion.heading_fusions == 0  # the three-dimensional fusion stays out
    assert mapper.fusion.open_direction_fusions >= 25
    assert mapper.fusion.open_direction_fusions_refused == 0
    assert slide < 0.03, slide


def test_karto_s_match_alone_slides_along_it(monkeypatch):
    """What holds it: Karto's best pose alone wanders along the corridor."""
    monkeypatch.setattr(OdometryFusion, "open_direction", lambda self, pred, inc, r: r.pose)
    slide, _ = slide_along_the_bare_stretch()
    assert slide > 0.2, slide


# -- the update itself --------------------------------------------------------------------


def trained_mapper() -> Mapper:
    """A mapper whose learnt odometry is good to about a centimetre over 0.5 m."""
    mapper = Mapper(SlamToolboxParams())
    rng = np.random.default_rng(0)
    for _ in range(200):
        e = rng.normal(0.0, [0.01, 0.01, 0.02])
        mapper.odometry_noise.observe(np.array([0.5, 0.0, 0.0]), e)
    assert mapper.odometry_noise.trusted
    return mapper


def corridor_match(yaw: float) -> MatchResult:
    """A match in a corridor running at `yaw`: 15 cm standard deviation along it, 3 cm
    across (Karto's, as on the corridor loop)."""
    c, s = math.cos(yaw), math.sin(yaw)
    r = np.array([[c, -s], [s, c]])
    cov = np.eye(3)
    cov[:2, :2] = r @ np.diag([0.15**2, 0.03**2]) @ r.T
    cov[2, 2] = math.radians(0.7) ** 2
    return MatchResult(np.array([2.0, 1.0, 0.3]), cov, 0.9, cov[2, 2])


def test_only_the_open_direction_moves_to_the_odometry():
    mapper = trained_mapper()
    step = np.array([0.5, 0.0, 0.0])
    for yaw in (0.0, 0.7, math.pi / 2, -2.0):
        match = corridor_match(yaw)
        u = np.array([math.cos(yaw), math.sin(yaw)])
        v = np.array([-u[1], u[0]])
        # the odometry 12 cm further along the corridor, 2 cm across, 3 degrees turned
        prediction = match.pose + np.array([*(0.12 * u + 0.02 * v), math.radians(3.0)])
        pose = mapper.fusion.open_direction(prediction, step, match)
        moved = pose[:2] - match.pose[:2]
        assert 0.11 < float(moved @ u) < 0.12  # nearly all the way along
        assert abs(float(moved @ v)) < 1e-12  # not across
        assert pose[2] == match.pose[2]  # nor in heading
    assert mapper.fusion.open_direction_fusions == 4


def test_odometry_that_disagrees_or_is_no_surer_leaves_the_match_alone():
    mapper = trained_mapper()
    step = np.array([0.5, 0.0, 0.0])
    match = corridor_match(0.0)
    # a wheel slip: the odometry 1 m along the corridor from the match
    slipped = match.pose + np.array([1.0, 0.0, 0.0])
    assert np.array_equal(mapper.fusion.open_direction(slipped, step, match), match.pose)
    assert mapper.fusion.open_direction_fusions_refused == 1
    # a match sure along every direction (a room): the odometry is no surer
    room = MatchResult(match.pose, np.diag([0.01**2, 0.01**2, 1e-4]), 0.9, 1e-4)
    near = room.pose + np.array([0.02, 0.0, 0.0])
    assert np.array_equal(mapper.fusion.open_direction(near, step, room), room.pose)
    assert mapper.fusion.open_direction_fusions == 0
