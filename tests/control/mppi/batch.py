"""Hand-made MPPI batches: a CriticData whose rollouts, path and costmap a test spells out.

Nav2's critics read `data.state` (velocities), `data.trajectories` (x, y, yaws), the
pruned path and its length; btnav's CriticData carries the same arrays, (batch, time)
float32. The costmap puts cell centres on multiples of 5 cm, so a point on a 5 cm grid
is never on a cell border.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from btnav.control.mppi.critic_data import CriticData
from btnav.costmap.cost_values import NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.costmap_ros import CostmapROS
from btnav.costmap.inflation_layer import InflationLayer
from btnav.params.costmap import CostmapParams

RES = 0.05
ORIGIN = -2.525  # cell (i, j) is centred on (ORIGIN + (i + 0.5) RES, ...): multiples of 5 cm
CELLS = 161  # the map spans [-2.525, 5.525) in x and y


def costmap(track_unknown: bool = False) -> Costmap2D:
    """A free 8 m square map; with `track_unknown`, unknown cells are traversable (as Nav2's
    layered costmap with track_unknown_space)."""
    cm = Costmap2D.empty(
        CELLS,
        CELLS,
        RES,
        ORIGIN,
        ORIGIN,
        frame_id="odom",
        default_value=NO_INFORMATION if track_unknown else 0,
    )
    cm.costs[:] = 0
    return cm


def cell(x: float, y: float) -> tuple[int, int]:
    """(row, column) of the cell whose centre is the 5 cm grid point (x, y)."""
    return round((y - ORIGIN) / RES - 0.5), round((x - ORIGIN) / RES - 0.5)


def paint(cm: Costmap2D, points, cost: int) -> Costmap2D:
    for x, y in points:
        cm.costs[cell(x, y)] = cost
    return cm


def line(x0: float, y0: float, heading: float, step: float, n: int, yaw: float | None = None):
    """n poses from (x0, y0), `step` apart along `heading`, facing `yaw` (the heading if None)."""
    k = np.arange(n)
    yaw = heading if yaw is None else yaw
    return np.stack(
        [x0 + k * step * math.cos(heading), y0 + k * step * math.sin(heading), np.full(n, yaw)],
        axis=-1,
    )


def straight_path(x1: float, step: float = 0.05, x0: float = 0.0) -> np.ndarray:
    """A path along +x from (x0, 0) to (x1, 0), `step` apart, yaw 0."""
    x = np.arange(round((x1 - x0) / step) + 1) * step + x0
    return np.stack([x, np.zeros_like(x), np.zeros_like(x)], axis=-1)


def polyline(*corners: tuple[float, float], step: float = 0.05) -> np.ndarray:
    """A path through `corners`, points `step` apart on each leg, yaw along each leg."""
    out = []
    for (ax, ay), (bx, by) in itertools.pairwise(corners):
        n = round(math.hypot(bx - ax, by - ay) / step)
        yaw = math.atan2(by - ay, bx - ax)
        t = np.arange(n) / n
        out.append(np.stack([ax + t * (bx - ax), ay + t * (by - ay), np.full(n, yaw)], -1))
    last = out[-1][-1, 2]
    out.append(np.array([[corners[-1][0], corners[-1][1], last]]))
    return np.concatenate(out)


def costmap_server(
    footprint=None, *, robot_radius: float = 0.22, k: float = 10.0, radius: float = 0.55
):
    """The local costmap server a controller is configured with: its footprint (a polygon,
    or the circle of `robot_radius`) and an inflation layer (cost_scaling_factor k,
    inflation_radius); `k=None`: no inflation layer. Critics read its footprint, radii and
    layer; the costs they score come from the hand-made grid in CriticData."""
    params = CostmapParams(footprint=footprint or (), robot_radius=robot_radius)
    layers = (
        []
        if k is None
        else [
            InflationLayer(
                "inflation_layer",
                InflationLayer.Params(cost_scaling_factor=k, inflation_radius=radius),
            )
        ]
    )
    return CostmapROS("local_costmap", params, layers)


#: A long robot, 1.0 x 0.3 m: inscribed radius 0.15 m, circumscribed 0.52 m.
LONG_ROBOT = [[0.5, 0.15], [0.5, -0.15], [-0.5, -0.15], [-0.5, 0.15]]


def path_length(path: np.ndarray) -> float:
    return float(np.hypot(*np.diff(path[:, :2], axis=0).T).sum())


def make_data(
    trajs=None,
    *,
    batch: int | None = None,
    steps: int | None = None,
    vx=None,
    vy=None,
    wz=None,
    path=None,
    robot=(0.0, 0.0, 0.0),
    goal=None,
    cm: Costmap2D | None = None,
    model_dt: float = 0.1,
    **kw,
) -> CriticData:
    """A CriticData for the rollouts `trajs` (a list of (T, 3) pose arrays), or for
    `batch` x `steps` rollouts standing at the origin when only velocities matter.
    Velocities default to zero; the goal defaults to the path's last pose."""
    if trajs is None:
        poses = np.zeros((batch, steps, 3), np.float32)
    else:
        poses = np.asarray(trajs, np.float32)
    b, t = poses.shape[:2]

    def f32(v):
        if v is None:
            return np.zeros((b, t), np.float32)
        return np.ascontiguousarray(np.broadcast_to(np.asarray(v, np.float32), (b, t)))

    vx, vy, wz = f32(vx), f32(vy), f32(wz)
    if path is None:
        path = np.array([robot, robot], np.float64) + np.array([[0, 0, 0], [10.0, 0, 0]])
    path = np.asarray(path, np.float32)
    goal = np.asarray(path[-1] if goal is None else goal, np.float64)
    return CriticData(
        vx=vx,
        vy=vy,
        wz=wz,
        cvx=vx.copy(),
        cvy=vy.copy(),
        cwz=wz.copy(),
        x=np.ascontiguousarray(poses[..., 0]),
        y=np.ascontiguousarray(poses[..., 1]),
        yaws=np.ascontiguousarray(poses[..., 2]),
        path=path,
        goal=goal,
        robot=np.asarray(robot, np.float64),
        robot_speed=(0.0, 0.0, 0.0),
        costmap=cm if cm is not None else costmap(),
        model_dt=model_dt,
        costs=np.zeros(b, np.float32),
        **kw,
    )
