"""The likelihood field against the simulated lidar on the office map drawn from its
world: where a scan fits the map best is where it was taken, with no half-cell offset.

nav2_amcl looks a beam end up in cell round((x - origin) / resolution) (its MAP_GXWX),
which reads map_server's cells (cell i spans [origin + i res, origin + (i + 1) res)) half
a cell low: its estimate sits ~2.5 cm off in x and in y on a 5 cm map. btnav floors, as
the OccupancyGrid does; this test keeps it that way (measured on the office tour, seeds
0-2: the rounding convention takes the mean RMS from 5.5 to 6.7 cm on the drawn map and
from 6.8 to 9.3 cm on the SLAM map).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from btnav.localization.amcl import LaserData, LikelihoodFieldModel, MapField
from btnav.maps import load_map
from btnav.sim.world import World
from btnav.sim.world_sensors import make_sensors

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "small_office.yaml"
MAP = REPO / "maps" / "small_office.yaml"


def test_the_likelihood_field_peaks_where_the_scan_was_taken_on_the_drawn_map():
    world = World.from_file(WORLD)
    lidar = make_sensors(world, seed=1)[0]
    mount = lidar.mount
    grid = load_map(MAP)
    field = MapField(grid, max_occ_dist=2.0)  # Nav2's amcl section
    model = LikelihoodFieldModel(z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_beams=60)
    rng = np.random.default_rng(0)
    rows, cols = np.nonzero(field.free & (field.occ_dist > 0.35))
    offsets = np.arange(-0.06, 0.0601, 0.005)
    gx, gy = (a.ravel() for a in np.meshgrid(offsets, offsets, indexing="ij"))
    best = []
    for _ in range(120):
        i = rng.integers(len(rows))
        x, y = grid.cell_to_world(np.array([[rows[i], cols[i]]]))[0] + rng.uniform(-0.025, 0.025, 2)
        yaw = rng.uniform(-math.pi, math.pi)
        c, s = math.cos(yaw), math.sin(yaw)
        pose = (x + c * mount.x - s * mount.y, y + s * mount.x + c * mount.y, yaw + mount.yaw)
        lidar.sensor_pose = lambda pose=pose: pose  # a scan from this pose (noise included)
        data = LaserData.from_scan(lidar.measure(0.0), (mount.x, mount.y, mount.yaw), -1, 100)
        poses = np.stack([x + gx, y + gy, np.full(gx.size, yaw)], axis=1)
        j = int(np.argmax(model.sensor_function(field, poses, data)))
        best.append((gx[j], gy[j]))
    bias = np.mean(best, axis=0)
    rms = math.sqrt(np.mean(np.sum(np.square(best), axis=1)))
    assert np.all(np.abs(bias) < 0.01), f"the scan fits the map best {bias * 100} cm off"
    assert rms < 0.035
