"""Karto's correlative scan matcher on synthetic rooms: poses recovered, responses and
covariances that mean what Karto's mean, the same bits every run."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core import fmath
from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D, angle_diff
from btnav.core.messages import LaserScan
from btnav.slam.karto import correlation_grid
from btnav.slam.karto.correlation_grid import (
    CorrelationGrid,
    find_valid_points,
    half_kernel_size,
    smear_kernel,
)
from btnav.slam.karto.scan_matcher import (
    MatcherParams,
    MatchResult,
    ScanMatcher,
    scan_reference_pose,
)

RANGE_MAX = 8.0
BEAMS = 360


# -- a small analytic world -----------------------------------------------------------


def laser_scan(stamp: float, ranges: np.ndarray) -> LaserScan:
    """A scan of the tests' full-circle lidar (BEAMS beams from -pi, out to RANGE_MAX)."""
    inc = 2 * math.pi / BEAMS
    return LaserScan(
        float(stamp),
        "laser",
        angle_min=-math.pi,
        angle_max=-math.pi + (BEAMS - 1) * inc,
        angle_increment=inc,
        range_min=0.1,
        range_max=RANGE_MAX,
        ranges=np.asarray(ranges, np.float32),
    )


def polyline(*pts: tuple[float, float]) -> np.ndarray:
    """Segments (S, 4) x0, y0, x1, y1 of a polyline."""
    p = np.asarray(pts, dtype=float)
    return np.hstack([p[:-1], p[1:]])


def box(cx: float, cy: float, w: float, h: float) -> np.ndarray:
    x0, x1, y0, y1 = cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2
    return polyline((x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0))


#: a 6 x 4 m room with a box, a corner wall and a pillar: no symmetry to fool a matcher
ROOM = np.vstack(
    [
        polyline((0, 0), (6, 0), (6, 4), (0, 4), (0, 0)),
        box(4.3, 1.1, 0.8, 0.6),
        polyline((1.0, 3.0), (1.9, 3.0), (1.9, 2.3)),
        box(2.6, 0.8, 0.25, 0.25),
    ]
)

#: a 20 m long, 2 m wide corridor: featureless along x
CORRIDOR = np.vstack([polyline((-10, -1), (10, -1)), polyline((-10, 1), (10, 1))])


def cast_ranges(walls: np.ndarray, pose: tuple[float, float, float]) -> np.ndarray:
    """The 360 ranges of a scan from `pose` (beams from -pi, inf where nothing is hit)."""
    x, y, yaw = pose
    beam = -math.pi + np.arange(BEAMS) * (2 * math.pi / BEAMS)
    s, c = fmath.sincos(beam + yaw)
    ax, ay, bx, by = (walls[:, i][None, :] for i in range(4))
    ex, ey = bx - ax, by - ay
    dx, dy = c[:, None], s[:, None]
    den = dx * ey - dy * ex
    wx, wy = ax - x, ay - y
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (wx * ey - wy * ex) / den
        u = (wx * dy - wy * dx) / den
    t = np.where((np.abs(den) > 1e-12) & (t > 1e-9) & (u >= 0) & (u <= 1), t, np.inf)
    return t.min(axis=1)


def raycast(
    walls: np.ndarray, pose: tuple[float, float, float], noise: float = 0.0, seed: int = 0
) -> np.ndarray:
    """(N, 2) end points in the robot frame of a 360-beam scan from `pose` (beam order,
    beams that hit nothing within RANGE_MAX left out)."""
    beam = -math.pi + np.arange(BEAMS) * (2 * math.pi / BEAMS)
    r = cast_ranges(walls, pose)
    if noise:
        r = r + np.random.default_rng(seed).normal(0.0, noise, r.shape)
    ok = (r > 0.12) & (r < RANGE_MAX)
    bs, bc = fmath.sincos(beam[ok])
    return np.stack([r[ok] * bc, r[ok] * bs], axis=1)


def reference_scans(walls, poses, noise=0.0):
    """(map-frame points, pose) per pose, as a mapper keeps its running scans."""
    out = []
    for i, p in enumerate(poses):
        pts = raycast(walls, p, noise, seed=100 + i)
        out.append((Pose2D(*p).transform_points(pts), np.array(p, dtype=float)))
    return out


def pose_error(result: MatchResult, truth) -> tuple[float, float]:
    d = math.hypot(result.pose[0] - truth[0], result.pose[1] - truth[1])
    return d, abs(angle_diff(float(result.pose[2]), truth[2]))


TRUE = (2.9, 2.0, 0.4)
NEIGHBOURS = [(2.5, 1.8, 0.2), (2.7, 1.9, 0.3), (3.1, 2.1, 0.5), (3.3, 2.3, 0.7), (2.2, 2.4, 0.1)]


@pytest.fixture(scope="module")
def sequential() -> ScanMatcher:
    return ScanMatcher(MatcherParams.sequential(range_threshold=RANGE_MAX))


# -- the sequential matcher -------------------------------------------------------------


def test_sequential_match_recovers_an_odometry_error(sequential):
    scan = raycast(ROOM, TRUE)
    guess = (TRUE[0] - 0.12, TRUE[1] + 0.08, TRUE[2] - 0.05)
    result = sequential.match(scan, np.array(guess), reference_scans(ROOM, NEIGHBOURS))
    dist, ang = pose_error(result, TRUE)
    assert dist < 0.01 and ang < math.radians(0.5), (result.pose, dist, math.degrees(ang))
    assert result.response > 0.6


def test_sequential_match_with_range_noise(sequential):
    scan = raycast(ROOM, TRUE, noise=0.01, seed=7)
    guess = (TRUE[0] - 0.12, TRUE[1] + 0.08, TRUE[2] - 0.05)
    result = sequential.match(scan, np.array(guess), reference_scans(ROOM, NEIGHBOURS, noise=0.01))
    dist, ang = pose_error(result, TRUE)
    assert dist < 0.02 and ang < math.radians(0.6), (result.pose, dist, math.degrees(ang))


def test_sequential_match_off_the_lattice(sequential):
    """An error that is no whole number of cells: the answer is within a cell."""
    truth = (3.337, 1.713, -0.52)
    scan = raycast(ROOM, truth)
    guess = (truth[0] + 0.173, truth[1] - 0.031, truth[2] + 0.081)
    ref = reference_scans(ROOM, [(3.0, 1.5, -0.3), (3.6, 1.9, -0.7), (3.2, 2.1, -0.4)])
    dist, ang = pose_error(sequential.match(scan, np.array(guess), ref), truth)
    assert dist < 0.01 and ang < math.radians(0.5), (dist, math.degrees(ang))


# -- the loop matcher -------------------------------------------------------------------


@pytest.mark.parametrize("offset", [(2.0, 0.0, 0.3), (-1.43, 1.37, -0.3)])
def test_loop_matcher_recovers_a_large_error_then_sequential_refines(sequential, offset):
    """As Karto's TryCloseLoop: the loop matcher unpenalised and unrefined, then the
    sequential matcher from its answer."""
    loop = ScanMatcher(MatcherParams.loop(range_threshold=RANGE_MAX))
    scan = raycast(ROOM, TRUE)
    guess = np.array(TRUE) - offset
    chain = reference_scans(ROOM, NEIGHBOURS)
    coarse = loop.match(scan, guess, chain, penalize=False, refine=False)
    dist, ang = pose_error(coarse, TRUE)
    # the 0.1 m x 0.0349 rad lattice, well inside the sequential search window
    assert dist < 0.12 and ang < math.radians(4.0), (coarse.pose, dist, math.degrees(ang))
    fine = sequential.match(scan, coarse.pose, chain, penalize=False)
    dist, ang = pose_error(fine, TRUE)
    assert dist < 0.01 and ang < math.radians(0.5), (fine.pose, dist, math.degrees(ang))


# -- responses and covariances ----------------------------------------------------------


def test_a_scan_from_another_room_scores_low(sequential):
    other = np.vstack([polyline((0, 0), (3, 0), (3, 5), (0, 5), (0, 0)), box(1.5, 3.5, 0.4, 1.0)])
    ref = reference_scans(ROOM, NEIGHBOURS)
    wrong = sequential.match(raycast(other, (1.2, 1.5, 0.0)), np.array(TRUE), ref)
    right = sequential.match(raycast(ROOM, TRUE), np.array(TRUE), ref)
    assert wrong.response < 0.3 < 0.9 < right.response
    assert wrong.covariance[0, 0] > right.covariance[0, 0]


def test_covariance_is_long_along_a_featureless_corridor(sequential):
    ref = reference_scans(CORRIDOR, [(-1.0, 0.0, 0.0), (-0.5, 0.1, 0.05), (0.5, -0.1, -0.05)])
    result = sequential.match(raycast(CORRIDOR, (0.0, 0.0, 0.0)), np.array((0.1, 0.05, 0.02)), ref)
    cov = result.covariance
    assert np.allclose(cov, cov.T)
    assert np.all(np.linalg.eigvalsh(cov) > 0)
    assert cov[0, 0] > 10 * cov[1, 1]
    assert abs(result.pose[1]) < 0.01 and abs(result.pose[2]) < math.radians(0.5)


def test_covariance_is_positive_definite_in_a_room(sequential):
    result = sequential.match(
        raycast(ROOM, TRUE), np.array(TRUE), reference_scans(ROOM, NEIGHBOURS)
    )
    assert np.all(np.linalg.eigvalsh(result.covariance) > 0)
    # Karto's floors: 0.1 (2 res)^2 / response on x, y; the fine headings' spread on yaw
    assert result.covariance[0, 0] >= 0.1 * 0.02**2


def test_response_expansion_finds_a_turn_beyond_the_angle_window(sequential):
    """Only a short far wall in view, the robot turned 0.6 rad more than odometry says:
    nothing scores inside +-0.349 rad, so Karto widens the window by 20 degrees."""
    wall = polyline((6.0, -0.5), (6.0, 0.5))
    ref = reference_scans(wall, [(0.0, 0.0, 0.0)])
    scan = raycast(wall, (0.0, 0.0, -0.6))
    found = sequential.match(scan, np.zeros(3), ref)
    assert abs(angle_diff(float(found.pose[2]), -0.6)) < math.radians(0.5)
    assert found.response > 0.5
    fixed = ScanMatcher(MatcherParams.sequential(RANGE_MAX, use_response_expansion=False))
    lost = fixed.match(scan, np.zeros(3), ref)
    assert lost.response == 0.0
    assert lost.covariance[0, 0] == lost.covariance[1, 1] == 500.0
    assert np.allclose(lost.pose, 0.0, atol=1e-9)


def test_an_empty_scan_keeps_the_guess_with_maximum_variance(sequential):
    guess = np.array((1.0, 2.0, 0.3))
    result = sequential.match(np.zeros((0, 2)), guess, reference_scans(ROOM, NEIGHBOURS))
    assert np.array_equal(result.pose, guess) and result.response == 0.0
    assert result.covariance[0, 0] == 500.0


def test_same_inputs_same_bits():
    scan = raycast(ROOM, TRUE, noise=0.01, seed=3)
    guess = np.array((TRUE[0] - 0.07, TRUE[1] + 0.11, TRUE[2] + 0.04))
    ref = reference_scans(ROOM, NEIGHBOURS, noise=0.01)
    runs = [
        ScanMatcher(MatcherParams.sequential(range_threshold=RANGE_MAX)).match(scan, guess, ref)
        for _ in range(2)
    ]
    a, b = runs
    assert a.pose.tobytes() == b.pose.tobytes()
    assert a.covariance.tobytes() == b.covariance.tobytes()
    assert a.response == b.response


# -- the correlation grid ---------------------------------------------------------------


def test_smear_kernel_is_kartos():
    k = smear_kernel(0.1, 0.01)
    assert half_kernel_size(0.1, 0.01) == 20 and k.shape == (41, 41)
    assert k[20, 20] == 100 and k[20, 0] == k[0, 20] == round(100 * math.exp(-2.0))
    assert np.array_equal(k, k.T) and np.array_equal(k, k[::-1])
    assert smear_kernel(0.03, 0.05).shape == (3, 3)


def _stamped(rows, cols, half, kernel, shape):
    """Karto's AddScan + SmearPoint, point by point."""
    grid = np.zeros(shape, np.uint8)
    for r, c in zip(rows, cols, strict=True):
        if grid[r, c] == 100:
            continue
        grid[r, c] = 100
        win = grid[r - half : r + half + 1, c - half : c + half + 1]
        np.maximum(win, kernel, out=win)
    return grid


@pytest.mark.parametrize(("smear", "res"), [(0.1, 0.01), (0.03, 0.05), (0.05, 0.02)])
@pytest.mark.parametrize("way", ["separable", "stamped"])
def test_grid_equals_stamping_the_kernel_per_point(smear, res, way, monkeypatch):
    """Both ways of smearing (picked by cost) give Karto's grid, cell for cell."""
    monkeypatch.setattr(correlation_grid, "_STAMP_COST", 0 if way == "stamped" else 10**9)
    rng = np.random.default_rng(1)
    # a wall, a corner and scattered points, seen from the centre (all facing it)
    t = np.linspace(0, 2 * math.pi, 200, endpoint=False)
    r = 1.0 + 0.3 * np.sin(3 * t) + rng.normal(0, 0.02, t.size)
    pts = np.stack([r * np.cos(t), r * np.sin(t)], axis=1)
    grid = CorrelationGrid.from_scans(
        [pts],
        np.zeros(2),
        np.zeros(2),
        resolution=res,
        smear_deviation=smear,
        roi_half_cells=10_000,
        pad=3,
    )
    valid = find_valid_points([pts], np.zeros(2))
    cells = grid.world_to_cell(pts[valid])
    half = half_kernel_size(smear, res)
    expect = _stamped(
        cells[:, 0] - grid.row0,
        cells[:, 1] - grid.col0,
        half,
        smear_kernel(smear, res),
        grid.data.shape,
    )
    assert np.array_equal(grid.data, expect)


@pytest.mark.parametrize(("count", "stride"), [(1, 1), (3, 1), (5, 2), (26, 2), (4, 3)])
def test_window_sums_equal_summing_each_translation(count, stride):
    """GetResponse's sums, lattice by lattice: points off the grid count 0, points whose
    window only grazes the smeared core count what they touch."""
    rng = np.random.default_rng(count * 10 + stride)
    pts = rng.uniform(-0.4, 0.4, (60, 2))
    pad = max((count - 1) * stride, 2)
    grid = CorrelationGrid.from_scans(
        [pts], np.zeros(2), np.zeros(2), resolution=0.02, smear_deviation=0.03,
        roi_half_cells=10_000, pad=pad,
    )  # fmt: skip
    angles, points = 3, 40
    first_row = grid.row0 + rng.integers(-pad - 3, grid.data.shape[0] + 3, (angles, points))
    first_col = grid.col0 + rng.integers(-pad - 3, grid.data.shape[1] + 3, (angles, points))
    sums = grid.window_sums(first_row, first_col, count, stride)
    expect = np.zeros((angles, count, count), np.int64)
    height, width = grid.data.shape
    for a in range(angles):
        for ty in range(count):
            for tx in range(count):
                r = first_row[a] + ty * stride - grid.row0
                c = first_col[a] + tx * stride - grid.col0
                inside = (r >= 0) & (r < height) & (c >= 0) & (c < width)
                expect[a, ty, tx] = grid.data[r[inside], c[inside]].astype(np.int64).sum()
    assert np.array_equal(sums, expect)


def test_matching_many_scans_on_one_shared_grid(sequential):
    """A grid built once for a reference serves scans from several guesses (as every scan
    between two processed scans is matched): each lands where its own grid puts it."""
    ref = reference_scans(ROOM, NEIGHBOURS)
    grid = sequential.correlation_grid(ref, np.array(TRUE[:2]), np.array((2.8, 2.0)), 9.0)
    for k, truth in enumerate([TRUE, (3.05, 2.12, 0.47), (2.71, 1.93, 0.31)]):
        scan = raycast(ROOM, truth, noise=0.005, seed=20 + k)
        guess = np.array((truth[0] + 0.09, truth[1] - 0.06, truth[2] + 0.04))
        shared = sequential.match(scan, guess, (), grid=grid)
        own = sequential.match(scan, guess, ref)
        dist, ang = pose_error(shared, truth)
        assert dist < 0.015 and ang < math.radians(0.5), (k, shared.pose, dist)
        assert math.hypot(*(shared.pose[:2] - own.pose[:2])) < 0.015
        assert abs(shared.response - own.response) < 0.05


def _karto_find_valid_points(points, viewpoint):
    """open_karto's FindValidPoints, line by line."""
    valid = []
    trailing = 0
    first = points[0]
    for i, cur in enumerate(points):
        dx, dy = first[0] - cur[0], first[1] - cur[1]
        if dx * dx + dy * dy > 0.01:
            a = viewpoint[1] - first[1]
            b = first[0] - viewpoint[0]
            c = first[1] * viewpoint[0] - first[0] * viewpoint[1]
            ss = cur[0] * a + cur[1] * b + c
            first = cur
            if ss < 0.0:
                trailing = i
            else:
                valid.extend(range(trailing, i))
                trailing = i
    mask = np.zeros(len(points), bool)
    mask[valid] = True
    return mask


def test_find_valid_points_is_kartos():
    scans = [Pose2D(*p).transform_points(raycast(ROOM, p)) for p in NEIGHBOURS]
    rng = np.random.default_rng(2)
    walk = np.cumsum(rng.normal(0, 0.06, (300, 2)), axis=0)
    scans.append(walk + np.array((3.0, 2.0)))  # a random walk: turns both ways
    for view in [(2.9, 2.0), (0.5, 0.5), (5.5, 3.5), (4.3, 2.5), (1.5, 3.5)]:
        v = np.array(view)
        expect = np.concatenate([_karto_find_valid_points(s, v) for s in scans])
        assert np.array_equal(find_valid_points(scans, v), expect), view
    # from behind the box (x 3.9-4.7, y 0.8-1.4), its far face is dropped
    box_scan = Pose2D(4.3, 0.4, 0.0).transform_points(raycast(ROOM, (4.3, 0.4, 0.0)))
    on_face = np.abs(box_scan[:, 1] - 0.8) < 1e-6
    keep = find_valid_points([box_scan], np.array((4.3, 2.0)))
    assert on_face.sum() > 10 and not keep[on_face].any() and keep[~on_face].mean() > 0.5


# -- parameters -------------------------------------------------------------------------


def test_params_errors_name_the_key():
    with pytest.raises(ParamsError, match="smear_deviation"):
        MatcherParams(0.5, 0.01, 0.2, 8.0)
    with pytest.raises(ParamsError, match="search_space_dimension"):
        MatcherParams(0.505, 0.01, 0.1, 8.0)
    with pytest.raises(ParamsError, match="range_threshold"):
        MatcherParams(0.5, 0.01, 0.1, 0.0)
    assert MatcherParams.loop(12.0).search_space_dimension == 8.0


def test_scan_reference_pose_is_the_barycenter_or_the_pose():
    pts = np.array([[1.0, 1.0], [3.0, 1.0], [2.0, 4.0]])
    pose = np.array([0.5, 0.5, 1.0])
    assert np.allclose(scan_reference_pose(pts, pose, True), (2.0, 2.0, 0.0))
    assert np.array_equal(scan_reference_pose(pts, pose, False), pose)


# -- every scan of a log matched (btnav slam's trajectory) ----------------------------


def test_scans_between_processed_scans_are_matched_not_dead_reckoned():
    """`btnav slam` gives every scan a pose. A scan the gate skips is laid onto the
    processed scans before and after it, so an odometry glitch between them (0.15 m and
    3 degrees for a few scans, as the Intel log's bursty stamps make) does not reach its
    pose; slam_toolbox's map -> odom times the odometry carries it."""
    from btnav.params.localization import SlamToolboxParams
    from btnav.slam.karto.offline import odometry_trajectory, run_slam
    from btnav.slam.logs import RecordedLog

    n = 61
    truth = np.column_stack([0.9 + 0.04 * np.arange(n), np.full(n, 1.8), np.linspace(0.0, 0.3, n)])
    stamps = 0.1 * np.arange(n)
    odom = truth.copy()
    glitch = np.arange(n)[(stamps > 2.55) & (stamps < 2.95)]
    odom[glitch] += (0.15, 0.0, math.radians(3.0))
    scans = [laser_scan(t, cast_ranges(ROOM, tuple(p))) for t, p in zip(stamps, truth, strict=True)]
    log = RecordedLog("synthetic", scans, stamps, odom, duration=float(stamps[-1]))
    params = SlamToolboxParams(max_laser_range=RANGE_MAX)
    result = run_slam(log, params)
    nodes = np.array([s.stamp for s in result.mapper.scans])
    skipped = ~np.isin(stamps, nodes)
    assert skipped[glitch].all() and 3 <= result.processed <= 8

    def errors(poses: np.ndarray) -> np.ndarray:
        return np.hypot(poses[:, 0] - truth[:, 0], poses[:, 1] - truth[:, 1])

    matched = errors(result.poses)
    node_of = np.searchsorted(nodes, stamps, side="right") - 1
    dead_reckoned = errors(odometry_trajectory(result.mapper, log.odom_at(stamps), node_of))
    assert matched[skipped].max() < 0.015, matched[skipped].max()
    assert dead_reckoned[glitch].min() > 0.1
    yaw = np.abs(np.angle(np.exp(1j * (result.poses[:, 2] - truth[:, 2]))))
    assert yaw.max() < math.radians(0.5)
