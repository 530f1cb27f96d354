"""AMCL's likelihood field measures the distance to a solid's surface, not to its inside.

nav2_amcl seeds its distance map with every occupied cell, so a beam ending deep inside
a filled block (a map drawn from a plan, or `btnav map from-world`) scores as a perfect
hit. In the aisle warehouse (solid 7 x 0.8 m shelf rows) a particle pushed towards a
shelf kept ~60% of the true pose's weight however deep it went, the cloud spread ~1.3 m
across a 2.2 m aisle, and the estimate jumped into the next aisle (5.8 m RMS with Nav2's
amcl section, seed 0). btnav seeds the field with the occupied cells that border a
non-occupied one; on maps of outlines (SLAM's, the bundled warehouse's walls) that is
every occupied cell and the field is nav2_amcl's.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.ndimage import distance_transform_edt

from btnav.core.geometry import Pose2D
from btnav.localization.amcl import LaserData, LikelihoodFieldModel, MapField
from btnav.maps import load_map
from btnav.maps.occupancy_grid import OccupancyGrid
from btnav.sim.world import World
from btnav.sim.world_sensors import make_sensors

REPO = Path(__file__).resolve().parents[2]
AISLE_WORLD = REPO / "worlds" / "aisle_warehouse.yaml"
AISLE_MAP = REPO / "maps" / "aisle_warehouse.yaml"


def nav2_seeded(field: MapField) -> MapField:
    """The same map with nav2_amcl's field: distance to the nearest occupied cell."""
    out = MapField(field.grid, field.max_occ_dist)
    dist = distance_transform_edt(~out.occupied) * out.resolution
    out.occ_dist = np.minimum(dist, out.max_occ_dist)
    return out


def test_a_filled_block_is_as_far_from_a_hit_as_its_depth_and_a_thin_wall_is_nav2s():
    data = np.zeros((40, 40), np.int8)
    data[10:30, 10:30] = 100  # a 1 x 1 m solid block at 0.05 m
    data[:, 35] = 100  # a one-cell wall
    field = MapField(OccupancyGrid(data, 0.05, Pose2D(0.0, 0.0, 0.0)), max_occ_dist=2.0)
    assert field.occ_dist[20, 20] == pytest.approx(0.45)  # the centre: 9 cells in
    assert field.occ_dist[10, 20] == 0.0 and field.occ_dist[12, 20] == pytest.approx(0.10)
    assert np.array_equal(field.occ_dist[:, 31:], nav2_seeded(field).occ_dist[:, 31:])
    # outside the block both fields agree: the surface is the nearest occupied cell there
    outside = data == 0
    assert np.allclose(field.occ_dist[outside], nav2_seeded(field).occ_dist[outside])


def test_a_pose_pushed_into_a_shelf_row_scores_low_on_the_aisle_map():
    world = World.from_file(AISLE_WORLD)
    lidar = make_sensors(world, seed=1)[0]
    mount = lidar.mount
    field = MapField(load_map(AISLE_MAP), max_occ_dist=2.0)  # Nav2's amcl section
    model = LikelihoodFieldModel(z_hit=0.5, z_rand=0.5, sigma_hit=0.2, max_beams=60)
    x, y = 5.0, 1.2  # the south floor: the wall 1.2 m south, the first row 1 m north
    sensor = (x + mount.x, y + mount.y, 0.0)
    lidar.sensor_pose = lambda: sensor
    data = LaserData.from_scan(lidar.measure(0.0), (mount.x, mount.y, mount.yaw), -1, 100)
    offsets = np.round(np.arange(-0.6, 0.61, 0.05), 2)
    poses = np.stack([np.full(offsets.size, x), y + offsets, np.zeros(offsets.size)], 1)
    f = model.sensor_function(field, poses, data)
    assert abs(offsets[np.argmax(f)]) <= 0.05
    truth = f[np.argmax(f)]
    into_shelf = (offsets >= 0.3) & (offsets <= 0.5)  # beams north end 0.3-0.5 m deep
    assert f[into_shelf].max() < 0.35 * truth
    # nav2_amcl's field keeps a plateau there: every beam ending inside the row is a hit
    nav2 = model.sensor_function(nav2_seeded(field), poses, data)
    assert nav2[into_shelf].min() > 0.55 * nav2.max()
    assert math.isclose(f[np.argmax(f)], nav2[np.argmax(f)], rel_tol=0.02)
