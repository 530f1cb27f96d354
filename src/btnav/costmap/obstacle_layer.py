"""nav2_costmap_2d::ObstacleLayer and VoxelLayer: obstacles marked and cleared from scans.

Each observation source (`observation_sources: scan`, then a `scan:` section) takes
LaserScans. A reading is transformed into the costmap's global frame with the frame
tree when it arrives (as Nav2 does at the scan's stamp). On update, as Nav2: every
clearing observation first frees the cells along its beams (from
`raytrace_min_range` to the reading, at most `raytrace_max_range`), then every
marking observation marks its end points closer than `obstacle_max_range` (and not
closer than `obstacle_min_range`) as LETHAL; finally the robot's footprint is
cleared (`footprint_clearing_enabled`).

Two departures keep an obstacle the lidar still sees in the costmap. Nav2 traces each
beam up to and including its return's cell and clears everything it passes out to
`raytrace_max_range`; with Nav2's own params (`obstacle_max_range` 2.5 <
`raytrace_max_range` 3.0) an obstacle 2.5-3 m away can only be cleared, never marked,
and beams grazing its face (a 5 cm cell is finer than where odometry puts a scan)
wipe it out. A door that closed behind the robot vanishes as the robot walks away,
the planner sends it back, the door reappears at 2.5 m, and the robot dithers at the
doorway (Nav2 issue 5476). So here (1) a beam clears LETHAL cells only as far as it
may mark them (`obstacle_max_range`; beyond, out to `raytrace_max_range`, it frees
unknown and inflated cells only), and (2) no beam frees a cell that holds a return
of its own scan. REP-117 values: `+inf` (no return) clears
up to the scanner's range when the source has `inf_is_valid` and is skipped
otherwise; it never marks. `-inf` and NaN are skipped. All beams of a scan are
traced at once: one numpy array of cells for the whole scan.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, model_validator

from ..core import fmath
from ..core.errors import FrameError
from ..core.frames import FrameTree
from ..core.geometry import Pose2D
from ..core.kernel_switch import Method, default_method
from ..core.messages import LaserScan
from ..params.schema import (
    FieldProblem,
    Names,
    ParamsModel,
    Why,
    ignored,
    named_sections,
    one_of,
)
from ..plugins import register
from .cost_values import FREE_SPACE, LETHAL_OBSTACLE
from .costmap_2d import Costmap2D
from .footprint import polygon_cells, transform_footprint
from .layer import Bounds, CostmapLayer, Window, combination_method_field
from .raytrace_kernel import clear_rays

#: Nav2 stores +inf returns as range_max minus a tenth of a millimetre.
INF_EPSILON = 1e-4

#: How the layer clears along its beams: raytrace_kernel's compiled loop, or trace_flat's
#: arrays (BTNAV_COSTMAP=numpy in the environment); the same cells either way.
DEFAULT_METHOD: Method = default_method("BTNAV_COSTMAP")


class ObservationSource(ParamsModel):
    """One sensor feeding an obstacle layer (Nav2's `<layer>.<source>.*` keys)."""

    data_type: one_of("LaserScan", "PointCloud2", "PointCloud") = "LaserScan"  # type: ignore[valid-type]
    marking: bool = True
    clearing: bool = False
    obstacle_max_range: float = Field(2.5, ge=0.0, description="m")
    obstacle_min_range: float = Field(0.0, ge=0.0, description="m")
    raytrace_max_range: float = Field(3.0, ge=0.0, description="m")
    raytrace_min_range: float = Field(0.0, ge=0.0, description="m")
    inf_is_valid: bool = False
    sensor_frame: str = Field("", description="overrides the scan's frame_id when set")
    observation_persistence: float = Field(0.0, ge=0.0, description="s; 0 keeps the latest only")
    expected_update_rate: float = Field(0.0, ge=0.0, description="s between readings; 0: no check")
    min_obstacle_height: float = ignored(0.0, "a planar scan has no height to filter")
    max_obstacle_height: float = ignored(2.0, "a planar scan has no height to filter")
    topic: str = ignored("", Why.TOPIC)
    transport_type: str = ignored("raw", Why.TOPIC)
    # Old spellings Nav2 Humble still read.
    clear_after_reading: bool = ignored(False, Why.ROS)


def _source_names(value: Any) -> Any:
    """Nav2 writes `observation_sources: scan bump` (a string) or a list."""
    if isinstance(value, str):
        return value.split()
    return value


class ObstacleLayerParams(CostmapLayer.Params):
    footprint_clearing_enabled: bool = True
    min_obstacle_height: float = ignored(0.0, "a planar scan has no height to filter")
    max_obstacle_height: float = ignored(2.0, "a planar scan has no height to filter")
    combination_method: int = combination_method_field()
    observation_sources: Names = []
    sources: dict[str, ObservationSource] = named_sections("observation_sources")
    tf_filter_tolerance: float = ignored(0.05, Why.TF, ge=0.0)
    transform_tolerance: float = ignored(0.2, Why.TF, ge=0.0)

    @model_validator(mode="before")
    @classmethod
    def _gather(cls, data: Any) -> Any:
        if not isinstance(data, Mapping):
            return data
        if "sources" in data:
            gathered = data["sources"]
            if isinstance(gathered, Mapping) and all(
                isinstance(v, ObservationSource) for v in gathered.values()
            ):
                return data  # a validated model being re-checked (attribute assignment)
            raise FieldProblem("sources", "unknown key 'sources'")
        out = dict(data)
        names = _source_names(out.get("observation_sources", []))
        if names is not None:
            out["observation_sources"] = names
        sections: dict[Any, Any] = {}
        if isinstance(names, list) and all(isinstance(n, str) for n in names):
            for name in names:
                if name in cls.model_fields:
                    raise FieldProblem(
                        "observation_sources", f"'{name}' is a key of this section, not a name"
                    )
                # Nav2 gives a source without a section its default keys.
                sections[name] = out.pop(name, None) or {}
        out["sources"] = sections
        return out


@dataclass
class Observation:
    """One scan in the global frame: its origin, marked points and clearing ray ends."""

    stamp: float
    origin: NDArray[np.float64]  # (2,)
    marks: NDArray[np.float64]  # (N, 2)
    ray_starts: NDArray[np.float64]  # (M, 2)
    ray_ends: NDArray[np.float64]  # (M, 2): up to obstacle_max_range, clearing anything
    far_starts: NDArray[np.float64]  # (F, 2): beyond it, out to raytrace_max_range,
    far_ends: NDArray[np.float64]  # (F, 2): clearing all but LETHAL cells
    returns: NDArray[np.float64]  # (K, 2): the beams' returns within raytrace_max_range


_DIRECTIONS: dict[tuple[float, float, int], tuple[NDArray[np.float64], NDArray[np.float64]]] = {}


def _beam_directions(
    angle_min: float, angle_increment: float, n: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """cos and sin of a scan's beam angles (`LaserScan.angles`), computed once per layout:
    every scan of a lidar has the same beams."""
    key = (angle_min, angle_increment, n)
    found = _DIRECTIONS.get(key)
    if found is None:
        a = angle_min + angle_increment * np.arange(n)
        s, c = fmath.sincos(a)  # the same bits on every CPU (np.cos/np.sin: not)
        found = (c, s)
        for v in found:
            v.setflags(write=False)
        if len(_DIRECTIONS) > 64:
            _DIRECTIONS.clear()
        _DIRECTIONS[key] = found
    return found


class _PendingObservation(Observation):
    """The `scan_observation` of a scan as it arrived (placed with the frame tree then),
    worked out when first read: a layer that updates less often than the lidar scans
    keeps only the latest scan (no `observation_persistence`), so most are never read."""

    _fields = ("origin", "marks", "ray_starts", "ray_ends", "far_starts", "far_ends", "returns")

    def __init__(self, scan: LaserScan, sensor_pose: Pose2D, source: ObservationSource) -> None:
        self.stamp = scan.stamp
        self._pending: tuple[LaserScan, Pose2D, ObservationSource] | None = (
            scan,
            sensor_pose,
            source,
        )

    def __getattr__(self, name: str) -> Any:
        pending = self.__dict__.get("_pending")
        if pending is None or name not in _PendingObservation._fields:
            raise AttributeError(name)
        obs = scan_observation(*pending, stamp=self.stamp)
        for field_name in _PendingObservation._fields:
            setattr(self, field_name, getattr(obs, field_name))
        self._pending = None
        return getattr(self, name)


def scan_observation(
    scan: LaserScan, sensor_pose: Pose2D, source: ObservationSource, stamp: float | None = None
) -> Observation:
    """The marking points and clearing rays of a scan, in the frame `sensor_pose` is given in."""
    r = np.asarray(scan.ranges, dtype=float)
    c, s = _beam_directions(scan.angle_min, scan.angle_increment, len(r))
    lo, hi = scan.range_min, scan.range_max
    finite = (r >= lo) & (r <= hi)  # NaN fails both; +-inf one of them when lo, hi are finite
    if not (math.isfinite(lo) and math.isfinite(hi)):
        finite &= np.isfinite(r)
    mark = finite & (r < source.obstacle_max_range)
    mark &= r >= source.obstacle_min_range
    rm = r[mark]
    marks = _placed(sensor_pose, rm * c[mark], rm * s[mark])
    # Clearing: valid readings, and +inf as "nothing up to range_max" when inf_is_valid.
    if source.inf_is_valid:
        length = np.where(finite, r, np.nan)
        length = np.where(np.isposinf(r), scan.range_max - INF_EPSILON, length)
        ok = np.isfinite(length)
        length = length[ok]
    else:
        ok = finite
        length = r[ok]
    returned = finite[ok] & (length <= source.raytrace_max_range)
    length = np.minimum(length, source.raytrace_max_range)
    start = source.raytrace_min_range
    keep = length > start
    cs, ss = c[ok][keep], s[ok][keep]
    length = length[keep]
    near = np.minimum(length, max(source.obstacle_max_range, start))
    far = length > near
    starts = _placed(sensor_pose, start * cs, start * ss)
    ends = _placed(sensor_pose, near * cs, near * ss)
    far_ends = _placed(sensor_pose, length[far] * cs[far], length[far] * ss[far])
    full = ends.copy()  # where each beam ends: near part, or far part when it has one
    full[far] = far_ends
    return Observation(
        scan.stamp if stamp is None else stamp,
        np.array([sensor_pose.x, sensor_pose.y]),
        marks,
        starts,
        ends,
        ends[far],
        far_ends,
        full[returned[keep]],
    )


def _placed(pose: Pose2D, px: NDArray[np.float64], py: NDArray[np.float64]) -> NDArray[np.float64]:
    """`pose.transform_points` of the points (px, py), without stacking them first."""
    s, c = fmath.sincos(pose.yaw)
    out = np.empty((len(px), 2))
    out[:, 0] = c * px - s * py + pose.x
    out[:, 1] = s * px + c * py + pose.y
    return out


def trace_cells(
    costmap: Costmap2D,
    origin: NDArray[np.float64],
    starts: NDArray[np.float64],
    ends: NDArray[np.float64],
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(my, mx) of every cell on the segments starts[i] -> ends[i], all rays at once.

    Ends are pulled back onto the map along their ray (as Nav2 does); a line visits
    one cell per step along its major axis, like Bresenham's. `origin` must be on the map.
    """
    flat = trace_flat(costmap, origin, starts, ends)
    ys, xs = np.divmod(flat, costmap.size_x)
    return ys.astype(np.int64, copy=False), xs.astype(np.int64, copy=False)


def trace_flat(
    costmap: Costmap2D,
    origin: NDArray[np.float64],
    starts: NDArray[np.float64],
    ends: NDArray[np.float64],
) -> NDArray[np.intp]:
    """`trace_cells` as flat indices `my * size_x + mx` (in the same order)."""
    if len(ends) == 0:
        return np.zeros(0, np.intp)
    res = costmap.resolution
    ny, nx = costmap.costs.shape
    lo, hi = _trace_box(costmap)
    # x and y as separate columns throughout (no reductions along a short axis)
    (o_x, o_y), (lo_x, lo_y) = origin, lo
    (up_x, up_y), (down_x, down_y) = hi - origin, lo - origin
    d = ends - origin
    dx, dy = d[:, 0], d[:, 1]
    # Largest t in [0, 1] keeping origin + t*d inside [lo, hi] on both axes (each bound
    # divided only where the ray heads for it: inf elsewhere).
    m = len(dx)
    t = np.divide(up_x, dx, out=np.full(m, np.inf), where=dx > 0)
    np.minimum(t, np.divide(down_x, dx, out=np.full(m, np.inf), where=dx < 0), out=t)
    np.minimum(t, np.divide(up_y, dy, out=np.full(m, np.inf), where=dy > 0), out=t)
    np.minimum(t, np.divide(down_y, dy, out=np.full(m, np.inf), where=dy < 0), out=t)
    t = np.clip(t, 0.0, 1.0)
    starts_t = fmath.dot_rows(starts - origin, d) / np.maximum(fmath.dot_rows(d, d), 1e-300)
    valid = starts_t <= t  # the start is still before the (clipped) end
    if not valid.all():
        t, dx, dy, starts = t[valid], dx[valid], dy[valid], starts[valid]
    # Continuous cell coordinates, sampled at most one cell apart along the major axis
    # (so no cell on the line is skipped), then floored: a DDA over every beam at once.
    f0x = (starts[:, 0] - lo_x) / res
    f0y = (starts[:, 1] - lo_y) / res
    f1x = (o_x + t * dx - lo_x) / res
    f1y = (o_y + t * dy - lo_y) / res
    dfx, dfy = f1x - f0x, f1y - f0y
    span = np.maximum(np.abs(dfx), np.abs(dfy))
    cells = np.maximum(np.abs(np.floor(f1x) - np.floor(f0x)), np.abs(np.floor(f1y) - np.floor(f0y)))
    n = np.maximum(np.ceil(span).astype(np.int64), cells.astype(np.int64))
    if n.size == 0:
        return np.zeros(0, np.intp)
    reps = n + 1
    total = int(reps.sum())
    longest = int(n.max())
    if len(n) * (longest + 1) <= 2 * total + 4096:
        # One row per beam, one column per step k = 0 .. max(n) (k <= n[i] are the beam's
        # samples): broadcasting instead of repeating, in the same row-major order.
        k = np.arange(longest + 1)
        frac = k.astype(np.float64) / np.maximum(n, 1).astype(np.float64)[:, None]
        fx = frac * dfx[:, None]
        fx += f0x[:, None]
        fy = frac * dfy[:, None]
        fy += f0y[:, None]
        keep = (k <= n[:, None]).ravel()
        fx, fy = fx.ravel(), fy.ravel()
    else:
        # A few beams much longer than the rest: one flat run of samples per beam instead.
        k = np.arange(total) - np.repeat(np.cumsum(reps) - reps, reps)
        frac = k / np.repeat(np.maximum(n, 1), reps)
        fx = np.repeat(f0x, reps)
        fx += frac * np.repeat(dfx, reps)
        fy = np.repeat(f0y, reps)
        fy += frac * np.repeat(dfy, reps)
        keep = None
    ix = np.floor(fx, out=fx).astype(np.intp)
    iy = np.floor(fy, out=fy).astype(np.intp)
    # 0 <= i < size as one unsigned test (a negative index wraps to a huge one)
    inside = ix.view(np.uintp) < nx
    inside &= iy.view(np.uintp) < ny
    if keep is not None:
        inside &= keep
    iy *= nx
    iy += ix
    return iy[inside]


def _trace_box(costmap: Costmap2D) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The corners a ray is pulled back between: the map's, the far one a hair inside."""
    res = costmap.resolution
    ny, nx = costmap.costs.shape
    lo = np.array([costmap.origin_x, costmap.origin_y])
    return lo, lo + np.array([nx * res, ny * res]) - 1e-6 * res


def free_along(
    costmap: Costmap2D,
    origin: NDArray[np.float64],
    starts: NDArray[np.float64],
    ends: NDArray[np.float64],
    keep_lethal: bool = False,
    method: Method = DEFAULT_METHOD,
) -> bool:
    """Free the cells `trace_flat` lists (but LETHAL ones with `keep_lethal`); whether it
    listed any."""
    costs = costmap.costs
    if method == "kernel" and costs.flags.c_contiguous and len(ends):
        lo, hi = _trace_box(costmap)
        ny, nx = costs.shape
        listed = clear_rays(
            costs.reshape(-1), nx, ny, costmap.resolution, origin, lo, hi, starts, ends,
            keep_lethal,
        )  # fmt: skip
        return bool(listed)
    flat = trace_flat(costmap, origin, starts, ends)
    if len(flat) == 0:
        return False
    if keep_lethal:
        flat = flat[costs.reshape(-1)[flat] != LETHAL_OBSTACLE]
    _set_flat(costs, flat, FREE_SPACE)
    return True


def _return_cells(
    grid: Costmap2D, returns: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(my, mx) of the cells holding a scan's returns (on the map)."""
    m, inside = grid.world_to_map(returns)
    return m[inside, 1], m[inside, 0]


def _set_flat(costs: NDArray[np.uint8], flat: NDArray[np.intp], value: int) -> None:
    """`costs.flat[flat] = value`, through a flat view when the grid is contiguous (a scan
    clears thousands of cells, often the same ones: 1D indexing is several times faster)."""
    if costs.flags.c_contiguous:
        costs.reshape(-1)[flat] = value
    else:
        ys, xs = np.divmod(flat, costs.shape[1])
        costs[ys, xs] = value


@register("costmap_layer", "nav2_costmap_2d::ObstacleLayer", aliases=("btnav/ObstacleLayer",))
class ObstacleLayer(CostmapLayer):
    """Marks scan hits as LETHAL and clears the cells the beams pass through."""

    Params = ObstacleLayerParams

    def __init__(self, name: str, params: ObstacleLayerParams | None = None) -> None:
        super().__init__(name, params)
        self.params: ObstacleLayerParams
        self.buffers: dict[str, list[Observation]] = {n: [] for n in self.params.sources}
        self.last_reading: dict[str, float] = {}
        self._footprint_cells: tuple[NDArray[np.int64], NDArray[np.int64]] | None = None
        #: The compiled raytrace or trace_flat's arrays (the same cells; BTNAV_COSTMAP=numpy).
        self.method: Method = DEFAULT_METHOD

    def on_params_changed(self) -> None:
        self.buffers = {n: self.buffers.get(n, []) for n in self.params.sources}

    # -- observations ------------------------------------------------------------------

    def laser_sources(self) -> list[str]:
        return [n for n, s in self.params.sources.items() if s.data_type == "LaserScan"]

    def receive_scan(
        self,
        scan: LaserScan,
        frame_tree: FrameTree,
        source: str | None = None,
        global_frame: str | None = None,
    ) -> None:
        """Buffer a scan for `source` (every LaserScan source when None), in the global frame."""
        names = [source] if source is not None else self.laser_sources()
        target = global_frame or (self.layered.global_frame if self.layered else "map")
        for name in names:
            if name not in self.params.sources:
                raise KeyError(f"layer '{self.name}' has no observation source '{name}'")
            cfg = self.params.sources[name]
            frame = cfg.sensor_frame or scan.frame_id
            try:
                pose = frame_tree.lookup(target, frame)
            except FrameError as err:
                raise err.located(key=f"{self.name}.{name}") from None
            obs = _PendingObservation(scan, pose, cfg)
            buf = self.buffers.setdefault(name, [])
            buf.insert(0, obs)
            keep = cfg.observation_persistence
            if keep == 0.0:
                del buf[1:]
            else:
                buf[:] = [o for o in buf if o.stamp >= obs.stamp - keep]
            self.last_reading[name] = scan.stamp

    def _observations(self, kind: str) -> list[Observation]:
        out = []
        for name, buf in self.buffers.items():
            cfg = self.params.sources.get(name)
            if cfg is not None and getattr(cfg, kind):
                out.extend(buf)
        return out

    def is_current(self, now: float) -> bool:
        """Whether every source with an `expected_update_rate` reported in time (Nav2's isCurrent)."""
        for name, cfg in self.params.sources.items():
            if cfg.expected_update_rate > 0.0:
                last = self.last_reading.get(name)
                if last is None or now - last > cfg.expected_update_rate:
                    return False
        return True

    # -- the two passes ---------------------------------------------------------------------

    def marks_allowed(self) -> bool:
        return True

    def update_bounds(self, robot: Pose2D, bounds: Bounds) -> None:
        if self.layered is None:
            return
        if self.layered.rolling_window:
            self.match_origin()
        if not self.enabled:
            return
        grid = self.grid
        lo = np.array([grid.origin_x, grid.origin_y])
        hi = lo + np.array(grid.size_in_meters)
        for obs in self._observations("clearing"):
            if np.any(obs.origin < lo) or np.any(obs.origin >= hi):
                continue  # Nav2: a sensor origin off the map cannot raytrace
            held = _return_cells(grid, obs.returns)
            saved = grid.costs[held]  # what a scan sees is not free (see the module doc)
            near = free_along(grid, obs.origin, obs.ray_starts, obs.ray_ends, False, self.method)
            if free_along(grid, obs.origin, obs.far_starts, obs.far_ends, True, self.method):
                bounds.touch_points(obs.far_ends)
            grid.costs[held] = saved
            if near:
                bounds.touch_points(obs.ray_ends)
                bounds.touch(float(obs.origin[0]), float(obs.origin[1]))
        if self.marks_allowed():
            for obs in self._observations("marking"):
                m, inside = grid.world_to_map(obs.marks)
                grid.costs[m[inside, 1], m[inside, 0]] = LETHAL_OBSTACLE
                bounds.touch_points(obs.marks[inside])
        if self.params.footprint_clearing_enabled:
            fp = transform_footprint(robot, self.layered.footprint)
            self._footprint_cells = polygon_cells(grid, fp)
            bounds.touch_points(fp)

    def update_costs(self, master: Costmap2D, window: Window) -> None:
        if not self.enabled or window.empty:
            return
        if self.params.footprint_clearing_enabled and self._footprint_cells is not None:
            ys, xs = self._footprint_cells
            self.grid.costs[ys, xs] = FREE_SPACE
        self.combine(master, window, self.params.combination_method)

    def reset(self) -> None:
        """Forget every obstacle and every buffered scan (btnav: a cleared costmap stays
        clear until a new scan arrives; Nav2 re-applies the last buffered one)."""
        super().reset()
        for buf in self.buffers.values():
            buf.clear()


class VoxelLayerParams(ObstacleLayerParams):
    z_voxels: int = Field(10, ge=1, le=16)
    origin_z: float = 0.0
    z_resolution: float = Field(0.2, gt=0.0, description="m")
    unknown_threshold: int = ignored(
        15, "btnav's scans are planar: a column is free once a beam crosses it", ge=0
    )
    mark_threshold: int = Field(0, ge=0, description="a planar scan marks one voxel per column")
    publish_voxel_map: bool = ignored(False, Why.VIZ)


@register("costmap_layer", "nav2_costmap_2d::VoxelLayer", aliases=("btnav/VoxelLayer",))
class VoxelLayer(ObstacleLayer):
    """Nav2's 3D obstacle layer, flattened: a planar lidar fills one voxel per column.

    It behaves as the obstacle layer and accepts the voxel keys. As in Nav2, a column
    is marked when it has more than `mark_threshold` marked voxels, so a planar scan
    marks only with `mark_threshold: 0` (Nav2's default and its params file's value).
    """

    Params = VoxelLayerParams

    def marks_allowed(self) -> bool:
        return self.params.mark_threshold < 1  # type: ignore[attr-defined]
