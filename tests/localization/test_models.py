"""AMCL's pieces against hand computations and statistics: motion models, laser models,
KLD sampling, low-variance resampling and clustering."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.core.messages import LaserScan
from btnav.localization.amcl import (
    BeamModel,
    DifferentialMotionModel,
    LaserData,
    LikelihoodFieldModel,
    LikelihoodFieldModelProb,
    MapField,
    OmniMotionModel,
    ParticleFilter,
)
from btnav.localization.amcl.bins import bin_keys, clusters, kld_count, kld_limit
from btnav.maps.occupancy_grid import OccupancyGrid

N = 200_000


def rng(seed: int = 0) -> np.random.Generator:
    return np.random.default_rng(seed)


# -- motion models ----------------------------------------------------------------------


def test_differential_noise_follows_the_alphas_on_a_straight_line():
    a1, a2, a3, a4 = 0.1, 0.2, 0.3, 0.4
    model = DifferentialMotionModel(a1, a2, a3, a4)
    t = 0.25
    out = model.odometry_update(np.zeros((N, 3)), (t, 0.0, 0.0), (t, 0.0, 0.0), rng())
    # rot1 = rot2 = 0: each turn has std sqrt(a2) t, the translation sqrt(a3) t
    assert out[:, 2].std() == pytest.approx(math.sqrt(2 * a2) * t, rel=0.02)
    sigma1 = math.sqrt(a2) * t  # E[cos(rot1_hat)] = exp(-sigma1^2 / 2)
    assert out[:, 0].mean() == pytest.approx(t * math.exp(-sigma1 * sigma1 / 2), abs=5e-4)
    assert out[:, 0].std() == pytest.approx(math.sqrt(a3) * t, rel=0.03)
    # sideways spread: trans_hat * sin(rot1_hat), E[trans_hat^2] = t^2 (1 + a3)
    assert out[:, 1].std() == pytest.approx(t * sigma1 * math.sqrt(1 + a3), rel=0.03)


def test_differential_noise_in_place_turn_and_backwards():
    a1, a4 = 0.2, 0.1
    model = DifferentialMotionModel(a1, 0.0, 0.0, a4)
    turn = 0.5
    out = model.odometry_update(np.zeros((N, 3)), (0.0, 0.0, turn), (0.0, 0.0, turn), rng(1))
    assert out[:, 2].mean() == pytest.approx(turn, abs=2e-3)
    assert out[:, 2].std() == pytest.approx(math.sqrt(a1) * turn, rel=0.02)
    # translation noise from the turn: std sqrt(a4) * turn, along the heading 0
    assert out[:, 0].std() == pytest.approx(math.sqrt(a4) * turn, rel=0.02)
    # backwards: rot1 = pi is read as no turn, so no rotation noise from alpha1
    back = model.odometry_update(np.zeros((N, 3)), (-0.3, 0.0, 0.0), (-0.3, 0.0, 0.0), rng(2))
    assert back[:, 0].mean() == pytest.approx(-0.3, abs=1e-3)
    assert np.abs(back[:, 2]).max() < 1e-9


def test_omni_strafe_noise_is_alpha5():
    a5 = 0.3
    model = OmniMotionModel(0.0, 0.0, 0.0, 0.0, a5)
    t = 0.4
    out = model.odometry_update(np.zeros((N, 3)), (t, 0.0, 0.0), (t, 0.0, 0.0), rng(3))
    assert out[:, 0].std() < 1e-9 and out[:, 0].mean() == pytest.approx(t)
    assert out[:, 1].std() == pytest.approx(math.sqrt(a5) * t, rel=0.02)
    # sideways motion in odom: the bearing follows it
    out = model.odometry_update(np.zeros((10, 3)), (0.0, t, 0.0), (0.0, t, 0.0), rng(3))
    assert out[:, 1].mean() == pytest.approx(t, abs=0.5)


# -- laser models -----------------------------------------------------------------------


def one_wall_map() -> OccupancyGrid:
    """2 x 2 m at 0.1 m, free, a wall along the column x in [1.5, 1.6)."""
    data = np.zeros((20, 20), np.int8)
    data[:, 15] = 100
    return OccupancyGrid(data, 0.1, Pose2D(0.0, 0.0, 0.0))


def scan(ranges: list[float], angle_min: float = 0.0, inc: float = 0.1) -> LaserScan:
    r = np.asarray(ranges, np.float32)
    return LaserScan(0.0, "laser", angle_min, angle_min + inc * (len(r) - 1), inc, 0.1, 4.0, r)


def test_likelihood_field_matches_a_hand_computation():
    field = MapField(one_wall_map(), max_occ_dist=2.0)
    model = LikelihoodFieldModel(z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_beams=2)
    # one particle at (0.55, 0.55) facing +x; two beams along x: ends at x=1.25 and 1.55
    data = LaserData.from_scan(scan([0.7, 1.0], inc=0.0), (0.0, 0.0, 0.0), -1, 100)
    poses = np.array([[0.55, 0.55, 0.0]])
    f = model.sensor_function(field, poses, data)
    expected = 1.0
    for d in (0.3, 0.0):  # cell centres 1.25 and 1.55 to the wall's centre 1.55
        pz = 0.5 * math.exp(-(d * d) / (2 * 0.2 * 0.2)) + 0.5 / 4.0
        expected += pz**3
    assert f[0] == pytest.approx(expected, rel=1e-12)
    # a beam off the map scores as max_occ_dist away; a max-range reading is skipped
    off = LaserData.from_scan(scan([3.0, 4.0], inc=0.0), (0.0, 0.0, 0.0), -1, 100)
    pz = 0.5 * math.exp(-4.0 / 0.08) + 0.125
    assert model.sensor_function(field, poses, off)[0] == pytest.approx(1 + pz**3, rel=1e-12)


def test_likelihood_field_peaks_at_the_true_pose_and_takes_the_laser_offset():
    field = MapField(one_wall_map(), max_occ_dist=2.0)
    model = LikelihoodFieldModel(z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_beams=30)
    angles = np.linspace(-0.6, 0.6, 13)
    laser = (0.1, 0.0, 0.0)  # 10 cm ahead of base_footprint
    true = np.array([0.5, 1.0, 0.0])
    ranges = (1.55 - true[0] - laser[0]) / np.cos(angles)
    data = LaserData.from_scan(scan(list(ranges), -0.6, 0.1), laser, -1, 100)
    xs = np.linspace(0.2, 0.8, 31)
    poses = np.stack([xs, np.full_like(xs, 1.0), np.zeros_like(xs)], 1)
    f = model.sensor_function(field, poses, data)
    assert abs(xs[np.argmax(f)] - true[0]) <= 0.05


def test_likelihood_field_prob_is_a_product_and_beam_skipping_drops_unexpected_beams():
    field = MapField(one_wall_map(), max_occ_dist=2.0)
    model = LikelihoodFieldModelProb(z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_beams=3)
    data = LaserData.from_scan(scan([1.0, 1.0, 0.3], inc=0.0), (0.0, 0.0, 0.0), -1, 100)
    poses = np.array([[0.55, 0.55, 0.0]])
    pz_wall = 0.5 + 0.125
    d = 0.7  # the third beam ends at x = 0.85: 0.7 from the wall (a person in the way)
    pz_short = 0.5 * math.exp(-(d * d) / 0.08) + 0.125
    f = model.sensor_function(field, poses, data)
    assert f[0] == pytest.approx(pz_wall * pz_wall * pz_short, rel=1e-12)
    skip = LikelihoodFieldModelProb(
        z_hit=0.5,
        z_rand=0.5,
        sigma_hit=0.2,
        max_beams=3,
        do_beamskip=True,
        beam_skip_distance=0.5,
        beam_skip_threshold=0.3,
        beam_skip_error_threshold=0.9,
    )
    assert skip.sensor_function(field, poses, data, converged=False)[0] == pytest.approx(f[0])
    g = skip.sensor_function(field, poses, data, converged=True)
    assert skip.skipped_beams == 1 and g[0] == pytest.approx(pz_wall * pz_wall, rel=1e-12)


def test_beam_model_casts_the_expected_range_to_the_wall():
    field = MapField(one_wall_map(), max_occ_dist=2.0)
    model = BeamModel(
        z_hit=0.5,
        z_rand=0.05,
        sigma_hit=0.05,
        max_beams=2,
        z_short=0.05,
        z_max=0.05,
        lambda_short=0.1,
    )
    xs = np.linspace(0.3, 0.9, 25)
    poses = np.stack([xs, np.full_like(xs, 1.0), np.zeros_like(xs)], 1)
    data = LaserData.from_scan(scan([1.0, 1.0], inc=0.0), (0.0, 0.0, 0.0), -1, 100)
    f = model.sensor_function(field, poses, data)
    assert abs(xs[np.argmax(f)] - 0.5) <= 0.05  # the wall's face is at x = 1.5


# -- particle filter ----------------------------------------------------------------------


def filter_(min_n: int = 100, max_n: int = 5000, seed: int = 0) -> ParticleFilter:
    return ParticleFilter(min_n, max_n, 0.0, 0.0, 0.05, 0.99, rng(seed))


def test_kld_limit_is_nav2s_formula():
    k = 10
    b = 2 / (9 * (k - 1))
    n = math.ceil((k - 1) / (2 * 0.05) * (1 - b + math.sqrt(b) * 0.99) ** 3)
    assert kld_limit(np.array([k]), 0.05, 0.99, 1, 10**6)[0] == n
    assert kld_limit(np.array([1]), 0.05, 0.99, 5, 77)[0] == 77  # one bin: max_samples


def test_kld_particle_count_shrinks_as_the_cloud_converges():
    pf = filter_()
    counts = []
    for spread in (3.0, 1.0, 0.3, 0.05):
        pf.init_gaussian((5.0, 5.0, 0.0), np.diag([spread**2, spread**2, (spread / 2) ** 2]))
        pf.resample(None)
        counts.append(pf.count)
    assert counts == sorted(counts, reverse=True) and counts[0] > 5 * counts[-1]
    assert counts[0] == 5000 and counts[-1] < 150  # min_particles 100, a few bins


def test_kld_count_stops_at_the_first_draw_past_the_limit():
    keys = np.zeros((1000, 3), np.int64)
    keys[:, 0] = np.arange(1000) % 50  # 50 distinct bins, all seen in the first 50 draws
    n = kld_count(keys, 0.05, 0.99, 10, 1000)
    assert n == kld_limit(np.array([50]), 0.05, 0.99, 10, 1000)[0] + 1


def test_low_variance_resampling_keeps_each_particle_in_proportion():
    pf = filter_(min_n=1000, max_n=1000)
    pf.poses = np.zeros((4, 3))
    pf.poses[:, 0] = [0.0, 10.0, 20.0, 30.0]  # far apart: each its own bin
    pf.weights = np.array([0.1, 0.2, 0.3, 0.4])
    pf.resample(None)
    counts = np.bincount((pf.poses[:, 0] / 10).astype(int), minlength=4)
    assert counts.tolist() == [100, 200, 300, 400]  # systematic: exact to one particle


def test_clusters_are_connected_bins_and_the_heaviest_is_the_estimate():
    pf = filter_()
    g = rng(5)
    a = np.column_stack([g.normal(2, 0.1, 600), g.normal(2, 0.1, 600), g.normal(0, 0.05, 600)])
    b = np.column_stack([g.normal(8, 0.1, 400), g.normal(6, 0.1, 400), g.normal(1, 0.05, 400)])
    pf.poses = np.vstack([a, b])
    pf.weights = np.full(1000, 1e-3)
    pf.cluster_stats()
    assert len(pf.clusters) == 2
    best = pf.best_cluster()
    assert best.weight == pytest.approx(0.6)
    assert best.mean[0] == pytest.approx(a[:, 0].mean()) and best.mean[1] == pytest.approx(
        2, abs=0.02
    )
    assert best.cov[0, 0] == pytest.approx(a[:, 0].var(), rel=1e-9)


def test_a_cloud_across_yaw_pi_is_one_cluster():
    g = rng(6)
    yaw = np.angle(np.exp(1j * (math.pi + g.normal(0, 0.1, 500))))
    poses = np.column_stack([g.normal(3, 0.05, 500), g.normal(3, 0.05, 500), yaw])
    label, count = clusters(bin_keys(poses))
    assert count == 1 and (label == 0).all()
    pf = filter_()
    pf.poses, pf.weights = poses, np.full(500, 1 / 500)
    pf.cluster_stats()
    assert abs(abs(pf.best_cluster().mean[2]) - math.pi) < 0.02


def test_recovery_injects_random_particles_when_weights_fall():
    pf = ParticleFilter(100, 1000, 0.001, 0.1, 0.05, 0.99, rng(7))
    pf.init_gaussian((1.0, 1.0, 0.0), np.diag([0.01, 0.01, 0.01]))
    pf.update_sensor(np.full(pf.count, 10.0))  # seeds w_slow = w_fast
    for _ in range(5):
        pf.update_sensor(np.full(pf.count, 2.0))  # the scan stops fitting
    assert pf.w_fast < pf.w_slow

    def far(n: int) -> np.ndarray:
        return np.tile([50.0, 50.0, 0.0], (n, 1))

    pf.resample(far)
    injected = (pf.poses[:, 0] == 50.0).mean()
    assert 0.1 < injected < 0.9 and pf.w_slow == pf.w_fast == 0.0
