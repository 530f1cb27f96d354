"""nav2_costmap_2d::StaticLayer: the map from map_server (or SLAM) as costs.

Occupancy values become costs as Nav2 interprets them, with the costmap's own
keys: `unknown_cost_value` means NO_INFORMATION (FREE_SPACE without
`track_unknown_space`), values >= `lethal_cost_threshold` are LETHAL, the rest FREE
with `trinary_costmap` or scaled to 0..254 without. A global costmap takes the
map's extent; a rolling window samples the map under it. When the map's cells
differ from the costmap's (resolution, origin, rotation, frame), each costmap cell
takes the worst of the map cells under it (lethal over unknown over free), so a
thin wall never falls between samples.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..core.geometry import Pose2D
from ..maps.occupancy_grid import OccupancyGrid
from ..params.schema import Why, ignored
from ..plugins import register
from .cost_values import FREE_SPACE, LETHAL_OBSTACLE, NO_INFORMATION
from .costmap_2d import Costmap2D
from .footprint import polygon_cells, transform_footprint
from .layer import Bounds, CostmapLayer, Window


def interpret_values(
    data: NDArray[np.int8],
    *,
    lethal_cost_threshold: int = 100,
    unknown_cost_value: int = 255,
    trinary_costmap: bool = True,
    track_unknown_space: bool = True,
) -> NDArray[np.uint8]:
    """OccupancyGrid values (-1, 0..100) -> costs, as Nav2's StaticLayer::interpretValue."""
    v = np.asarray(data).astype(np.int16) & 0xFF  # read as unsigned char: -1 -> 255
    if trinary_costmap:
        scaled = np.zeros(v.shape, np.int16)
    else:
        threshold = max(lethal_cost_threshold, 1)
        scaled = (v / threshold * LETHAL_OBSTACLE).astype(np.int16)
    out = np.where(v >= lethal_cost_threshold, LETHAL_OBSTACLE, scaled)
    out = np.where(
        v == unknown_cost_value, NO_INFORMATION if track_unknown_space else FREE_SPACE, out
    )
    return out.astype(np.uint8)


#: Sampling order for resampling: the worst cost wins, lethal over unknown over the rest.
def _rank(costs: NDArray[np.uint8]) -> NDArray[np.int16]:
    r = costs.astype(np.int16)
    r[costs == NO_INFORMATION] = 254  # below lethal (255 after the swap below)
    r[costs == LETHAL_OBSTACLE] = 255
    return r


def _unrank(rank: NDArray[np.int16]) -> NDArray[np.uint8]:
    out = rank.astype(np.uint8)
    out[rank == 254] = NO_INFORMATION
    out[rank == 255] = LETHAL_OBSTACLE
    return out


def resample(
    costs: NDArray[np.uint8],
    grid_resolution: float,
    grid_pose: Pose2D,
    target: Costmap2D,
    window: tuple[int, int, int, int] | None = None,
    outside: int = NO_INFORMATION,
) -> NDArray[np.uint8]:
    """Costs of a grid (origin `grid_pose` in the target's frame) sampled onto `target`'s cells.

    Each target cell takes the worst of k x k samples (k = ceil(target res / grid res)),
    so downsampling keeps thin obstacles. Cells off the grid get `outside`.
    """
    x0, y0, xn, yn = window or (0, 0, target.size_x, target.size_y)
    k = max(1, math.ceil(target.resolution / grid_resolution - 1e-9))
    offs = (np.arange(k) + 0.5) / k * target.resolution
    xs = target.origin_x + np.arange(x0, xn) * target.resolution
    ys = target.origin_y + np.arange(y0, yn) * target.resolution
    best = np.full((yn - y0, xn - x0), -1, np.int16)
    rank = _rank(costs)
    h, w = costs.shape
    outside_rank = _rank(np.array([outside], np.uint8))[0]
    for oy in offs:  # k*k whole-grid passes (k is 1 when resolutions match)
        for ox in offs:
            px, py = np.broadcast_arrays((xs + ox)[None, :], (ys + oy)[:, None])
            local = grid_pose.inverse_transform_points(np.stack([px, py], axis=-1))
            col = np.floor(local[..., 0] / grid_resolution).astype(np.int64)
            row = np.floor(local[..., 1] / grid_resolution).astype(np.int64)
            ok = (col >= 0) & (col < w) & (row >= 0) & (row < h)
            sample = np.full(ok.shape, outside_rank, np.int16)
            sample[ok] = rank[row[ok], col[ok]]
            np.maximum(best, sample, out=best)
    return _unrank(best)


@register("costmap_layer", "nav2_costmap_2d::StaticLayer", aliases=("btnav/StaticLayer",))
class StaticLayer(CostmapLayer):
    """The static map. Give it a map with `set_map` (the costmap does it for map_server's)."""

    class Params(CostmapLayer.Params):
        footprint_clearing_enabled: bool = False
        restore_cleared_footprint: bool = True
        subscribe_to_updates: bool = ignored(
            False, "btnav hands the map to the costmap directly (set_map); every new map is used"
        )
        map_subscribe_transient_local: bool = ignored(True, Why.QOS)
        map_topic: str = ignored("", Why.TOPIC)
        transform_tolerance: float = ignored(0.0, Why.TF, ge=0.0)

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.params: StaticLayer.Params
        self.map: OccupancyGrid | None = None
        self.map_costs: NDArray[np.uint8] | None = None
        self.has_updated_data = False
        self._footprint_cells: tuple[NDArray[np.int64], NDArray[np.int64]] | None = None

    # -- the map ---------------------------------------------------------------------

    def set_map(self, grid: OccupancyGrid) -> None:
        """A new map (map_server's, or SLAM's latest): a global costmap takes its extent."""
        self.map = grid
        self._interpret()
        layered = self.layered
        if layered is not None and not layered.rolling_window:
            res = layered.resolution
            sx = max(1, round(grid.width * grid.resolution / res))
            sy = max(1, round(grid.height * grid.resolution / res))
            m = layered.costmap
            if (m.size_x, m.size_y, m.resolution, m.origin_x, m.origin_y) != (
                sx,
                sy,
                res,
                grid.origin.x,
                grid.origin.y,
            ):
                layered.resize_map(sx, sy, res, grid.origin.x, grid.origin.y)  # calls match_size
            else:
                self._fill_grid()
        self.has_updated_data = True

    def _interpret(self) -> None:
        assert self.map is not None
        cp = self.layered.params if self.layered is not None else None
        self.map_costs = interpret_values(
            self.map.data,
            lethal_cost_threshold=cp.lethal_cost_threshold if cp else 100,
            unknown_cost_value=cp.unknown_cost_value if cp else 255,
            trinary_costmap=cp.trinary_costmap if cp else True,
            track_unknown_space=self.layered.track_unknown_space if self.layered else True,
        )

    def on_initialize(self) -> None:
        if self.map is not None:
            self.set_map(self.map)

    def match_size(self) -> None:
        super().match_size()
        self._fill_grid()
        self.has_updated_data = True

    def _map_pose(self) -> Pose2D | None:
        """The map's origin in the costmap's global frame."""
        assert self.map is not None and self.layered is not None
        frame = self.map.frame_id
        if frame == self.layered.global_frame:
            return self.map.origin
        tree = self.layered.frame_tree
        if tree is None or not (tree.has(frame) and tree.has(self.layered.global_frame)):
            return None
        return tree.lookup(self.layered.global_frame, frame) @ self.map.origin

    def _fill_grid(self, window: Window | None = None) -> None:
        """Sample the map onto this layer's grid (the whole grid, or a window of it)."""
        if self.map is None or self.map_costs is None or self.layered is None:
            return
        pose = self._map_pose()
        if pose is None:
            return
        g = self.grid
        win = (
            (0, 0, g.size_x, g.size_y)
            if window is None
            else (window.x0, window.y0, window.xn, window.yn)
        )
        if window is not None and window.empty:
            return
        same = (
            pose.yaw == 0.0
            and self.map.resolution == g.resolution
            and pose.x == g.origin_x
            and pose.y == g.origin_y
            and self.map_costs.shape == g.costs.shape
        )
        if same:
            g.costs[win[1] : win[3], win[0] : win[2]] = self.map_costs[
                win[1] : win[3], win[0] : win[2]
            ]
        else:
            g.costs[win[1] : win[3], win[0] : win[2]] = resample(
                self.map_costs, self.map.resolution, pose, g, win, outside=g.default_value
            )

    # -- the two passes ------------------------------------------------------------------

    def update_bounds(self, robot: Pose2D, bounds: Bounds) -> None:
        if self.map is None or self.layered is None:
            return
        if self.params.footprint_clearing_enabled:
            fp = transform_footprint(robot, self.layered.footprint)
            self._footprint_cells = polygon_cells(self.master, fp)
            bounds.touch_points(fp)
        if self.layered.rolling_window:
            self.match_origin()
            self._fill_grid()  # the window moved under the map
            bounds.cover(self.master)
            return
        if self.has_updated_data:
            bounds.cover(self.master)
            self.has_updated_data = False

    def update_costs(self, master: Costmap2D, window: Window) -> None:
        if not self.enabled or self.map is None or window.empty:
            return
        cleared = None
        if self.params.footprint_clearing_enabled and self._footprint_cells is not None:
            ys, xs = self._footprint_cells
            cleared = (ys, xs, self.grid.costs[ys, xs].copy())
            self.grid.costs[ys, xs] = FREE_SPACE
        cp = self.layered.params if self.layered is not None else None
        if cp is not None and cp.use_maximum:
            self.update_with_max(master, window)
        else:
            self.update_with_true_overwrite(master, window)
        if cleared is not None and self.params.restore_cleared_footprint:
            ys, xs, old = cleared
            self.grid.costs[ys, xs] = old

    def reset(self) -> None:
        # The map is not sensed data: a reset re-applies it (as Nav2's StaticLayer::reset).
        self.has_updated_data = True
        self.current = True

    def is_clearable(self) -> bool:
        return False

    def clear_area(self, window: Window, invert: bool) -> None:
        return
