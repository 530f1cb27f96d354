"""The compiled beam ends give the numpy path's table indices, so AMCL's weights (and the
demo's trajectory) are the same bits with BTNAV_AMCL=numpy or without."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.core.messages import LaserScan
from btnav.localization.amcl import (
    LaserData,
    LikelihoodFieldModel,
    LikelihoodFieldModelProb,
    laser_models,
)
from btnav.localization.amcl.likelihood_field import MapField
from btnav.maps.occupancy_grid import OccupancyGrid


def random_field(rng: np.random.Generator) -> MapField:
    """A map with random walls, unknown patches, resolution and origin (yaw too)."""
    ny, nx = int(rng.integers(5, 80)), int(rng.integers(5, 80))
    data = rng.choice(np.array([0, 0, 0, 0, 100, -1], np.int8), size=(ny, nx))
    yaw = float(rng.choice([0.0, 0.0, rng.uniform(-3.0, 3.0)]))
    origin = Pose2D(*rng.uniform(-4.0, 4.0, 2), yaw)
    res = float(rng.choice([0.05, 0.1, 0.025]))
    return MapField(OccupancyGrid(data, res, origin), max_occ_dist=float(rng.uniform(0.3, 2.0)))


def random_scan(rng: np.random.Generator, beams: int) -> LaserScan:
    """Ranges with short, max-range and NaN readings among them."""
    r = rng.uniform(0.0, 6.0, beams).astype(np.float32)
    r[rng.random(beams) < 0.1] = np.nan
    r[rng.random(beams) < 0.1] = 5.0
    inc = float(rng.uniform(0.005, 0.05))
    angle_min = float(rng.uniform(-3.2, 0.0))
    return LaserScan(0.0, "laser", angle_min, angle_min + inc * (beams - 1), inc, 0.1, 5.0, r)


def weights(model, field, poses, data, method: str, converged: bool) -> np.ndarray:
    model.method = method
    return model.sensor_function(field, poses, data, converged)


@pytest.mark.parametrize("seed", range(30))
@pytest.mark.parametrize("model_cls", [LikelihoodFieldModel, LikelihoodFieldModelProb])
def test_random_particles_and_scans_weigh_the_same_bits(seed: int, model_cls) -> None:
    rng = np.random.default_rng(seed)
    field = random_field(rng)
    n = int(rng.integers(1, 600))
    lo = np.array([field.origin.x, field.origin.y]) - 1.0
    span = np.array([field.width, field.height]) * field.resolution + 2.0
    poses = np.empty((n, 3))
    on_map = rng.random() < 0.5  # every particle on the map (no clipping) or some off it
    scale = rng.uniform(0.3, 0.7, (n, 2)) if on_map else rng.uniform(-0.5, 1.5, (n, 2))
    poses[:, :2] = lo + scale * span
    poses[:, 2] = rng.uniform(-np.pi, np.pi, n)
    laser = (
        float(rng.uniform(-0.3, 0.3)),
        float(rng.uniform(-0.1, 0.1)),
        float(rng.uniform(-1, 1)),
    )
    data = LaserData.from_scan(random_scan(rng, int(rng.integers(2, 400))), laser, -1, -1)
    model = model_cls(
        z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_beams=int(rng.integers(2, 120)),
        do_beamskip=True,
    )  # fmt: skip
    converged = bool(rng.integers(0, 2))
    numpy_w = weights(model, field, poses, data, "numpy", converged)
    numpy_skipped = model.skipped_beams
    kernel_w = weights(model, field, poses, data, "kernel", converged)
    assert kernel_w.tobytes() == numpy_w.tobytes()
    assert model.skipped_beams == numpy_skipped


def test_the_models_take_the_kernel_unless_btnav_amcl_says_numpy(monkeypatch) -> None:
    model = LikelihoodFieldModel(z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_beams=60)
    assert model.method == laser_models.DEFAULT_METHOD
    monkeypatch.setattr(laser_models, "DEFAULT_METHOD", "numpy")
    assert LikelihoodFieldModel(z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_beams=60).method == (
        "numpy"
    )


_COMPILE = """
import numpy as np
from btnav.localization.amcl.beam_ends_kernel import beam_end_cells
v = np.linspace(0.0, 1.0, 4)
beam_end_cells(v, v, v, v, v, v, 10, 10, True, np.empty((4, 4), np.intp))
"""


def test_no_fused_multiply_add_in_the_kernel(fused_multiply_adds) -> None:
    n_chars, n_fused = fused_multiply_adds(_COMPILE, "(beam_end_cells,)")
    assert n_chars > 1000  # the assembly was read
    assert n_fused == 0


@pytest.mark.slow
def test_the_amcl_run_is_the_same_bytes_on_numpy_and_on_numbas_generic_cpu(
    tmp_path, short_run_digest
) -> None:
    kernel = short_run_digest(tmp_path / "kernel")
    assert short_run_digest(tmp_path / "numpy", BTNAV_AMCL="numpy") == kernel
    # a fresh cache: every kernel compiles for numba's baseline x86-64, no AVX or FMA
    generic = {"NUMBA_CPU_NAME": "generic", "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    assert short_run_digest(tmp_path / "generic", **generic) == kernel
