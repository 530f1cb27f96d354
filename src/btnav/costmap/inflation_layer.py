"""nav2_costmap_2d::InflationLayer: costs that decay with the distance to the nearest obstacle.

Nav2's cost function, on the distance d (metres, between cell centres) to the
nearest lethal cell: 254 at the obstacle, 253 while d <= the robot's inscribed
radius, then `int(252 * exp(-cost_scaling_factor * (d - inscribed_radius)))`, and
nothing beyond `inflation_radius` (rounded up to whole cells, as Nav2 does).
Nav2 propagates a wavefront cell by cell; here the exact Euclidean distance to the
nearest obstacle is found over the window at once: by scipy's distance transform on the
numpy path, by a compiled pass bounded by the inflation radius otherwise
(inflation_kernel; BTNAV_COSTMAP=numpy runs the numpy path, the same costs).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from pydantic import Field
from scipy.ndimage import distance_transform_edt

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.kernel_switch import Method, default_method
from ..plugins import register
from .cost_values import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
)
from .costmap_2d import Costmap2D
from .inflation_kernel import inflate_window
from .layer import Bounds, Layer, Window

#: inflation_kernel's compiled pass, or scipy's transform (BTNAV_COSTMAP=numpy).
DEFAULT_METHOD: Method = default_method("BTNAV_COSTMAP")


def inflation_cost(
    distance_m: NDArray[np.float64] | float,
    inscribed_radius: float,
    cost_scaling_factor: float,
    inflation_radius: float | None = None,
) -> NDArray[np.uint8]:
    """Nav2's computeCost on distances in metres (0 means the obstacle cell itself)."""
    d = np.asarray(distance_m, dtype=float)
    factor = fmath.exp(-cost_scaling_factor * (d - inscribed_radius))
    decayed = np.floor((INSCRIBED_INFLATED_OBSTACLE - 1) * np.minimum(factor, 1.0))
    cost = np.where(
        d == 0,
        LETHAL_OBSTACLE,
        np.where(d <= inscribed_radius, INSCRIBED_INFLATED_OBSTACLE, decayed),
    )
    if inflation_radius is not None:
        cost = np.where(d > inflation_radius, FREE_SPACE, cost)
    return cost.astype(np.uint8)


@register("costmap_layer", "nav2_costmap_2d::InflationLayer", aliases=("btnav/InflationLayer",))
class InflationLayer(Layer):
    """Inflates lethal cells of the master grid by the robot's inscribed radius and a decay."""

    class Params(Layer.Params):
        inflation_radius: float = Field(0.55, ge=0.0, description="m")
        cost_scaling_factor: float = Field(10.0, ge=0.0)
        inflate_unknown: bool = False
        inflate_around_unknown: bool = False

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.params: InflationLayer.Params
        self.need_reinflation = True
        self._last_bounds = Bounds()
        self._table: NDArray[np.uint8] = np.zeros(1, np.uint8)
        self._table_key: tuple[int, float, float, float] | None = None
        #: The compiled pass or scipy's transform (the same costs; BTNAV_COSTMAP=numpy).
        self.method: Method = DEFAULT_METHOD

    @property
    def inscribed_radius(self) -> float:
        return self.layered.inscribed_radius if self.layered is not None else 0.0

    def cell_inflation_radius(self) -> int:
        return self.master.cell_distance(self.params.inflation_radius)

    def on_footprint_changed(self) -> None:
        self.need_reinflation = True

    def on_params_changed(self) -> None:
        self.need_reinflation = True

    def match_size(self) -> None:
        self.need_reinflation = True

    def reset(self) -> None:
        self.need_reinflation = True
        self.current = True

    def update_bounds(self, robot: Pose2D, bounds: Bounds) -> None:
        if self.need_reinflation:
            # Everything: the cost function or the grid changed.
            self._last_bounds = Bounds()
            self._last_bounds.merge(bounds)
            bounds.cover(self.master)
            self.need_reinflation = False
            return
        # Where costs changed now or last time (so removed obstacles lose their inflation).
        previous, self._last_bounds = self._last_bounds, Bounds()
        self._last_bounds.merge(bounds)
        if bounds.empty and previous.empty:
            return
        grown = Bounds()
        grown.merge(bounds)
        grown.merge(previous)
        grown = grown.expanded(self.params.inflation_radius)
        bounds.merge(grown)

    def _cost_table(self, r: int, resolution: float) -> NDArray[np.uint8]:
        """The cost at each squared cell distance 0 .. r*r (0 beyond: one more entry), as
        `inflation_cost` gives it for the distance the distance transform computes."""
        key = (r, resolution, self.inscribed_radius, self.params.cost_scaling_factor)
        if self._table_key != key:
            squared = np.arange(r * r + 2, dtype=np.float64)
            table = inflation_cost(np.sqrt(squared) * resolution, self.inscribed_radius, key[3])
            table[-1] = FREE_SPACE
            self._table, self._table_key = table, key
        return self._table

    def update_costs(self, master: Costmap2D, window: Window) -> None:
        if not self.enabled or window.empty:
            return
        p = self.params
        r = self.cell_inflation_radius()
        if self.method == "kernel":
            table = self._cost_table(r, master.resolution)
            inflate_window(master.costs, window.x0, window.y0, window.xn, window.yn, r, table,
                           p.inflate_around_unknown, p.inflate_unknown)  # fmt: skip
            return
        # Obstacles up to r cells outside the window still inflate into it.
        x0, y0 = max(window.x0 - r - 1, 0), max(window.y0 - r - 1, 0)
        xn, yn = min(window.xn + r + 1, master.size_x), min(window.yn + r + 1, master.size_y)
        region = master.costs[y0:yn, x0:xn]
        seeds = region == LETHAL_OBSTACLE
        if p.inflate_around_unknown:
            seeds |= region == NO_INFORMATION
        if not seeds.any():
            return
        # The nearest seed of every cell (scipy's exact Euclidean feature transform); the
        # squared distances in cells are integers, worked out only over the window.
        near_y, near_x = distance_transform_edt(
            ~seeds, return_distances=False, return_indices=True
        )[:, window.y0 - y0 : window.yn - y0, window.x0 - x0 : window.xn - x0]
        dy = near_y - np.arange(window.y0 - y0, window.yn - y0)[:, None]
        dx = near_x - np.arange(window.x0 - x0, window.xn - x0)
        squared = dy * dy
        squared += dx * dx
        near = squared <= r * r  # (the distance sqrt(squared) <= r)
        if not near.any():
            return
        # The cost of each squared distance is worked out once (Nav2's cached_costs_),
        # then looked up.
        table = self._cost_table(r, master.resolution)
        np.minimum(squared, len(table) - 1, out=squared)
        cost = table[squared]
        old = master.costs[window.slices]
        unknown = old == NO_INFORMATION
        # Unknown cells take the inflated cost only when it is "inscribed" or worse,
        # or any positive cost with inflate_unknown; the others keep the higher cost.
        threshold = FREE_SPACE + 1 if p.inflate_unknown else INSCRIBED_INFLATED_OBSTACLE
        take = np.where(unknown, near & (cost >= threshold), near & (cost > old))
        np.copyto(old, cost, where=take)
