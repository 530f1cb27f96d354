"""Cartographer's pose graph as one `.npz` file (the role of its `.pbstream`), for looking at.

Unlike slam_toolbox's file (`karto.graph_io`) it holds no scans: `mode: localization`
loads slam_toolbox's graphs only.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from .slam import CartographerMapper

CARTOGRAPHER_FORMAT = "btnav-cartographer-graph-1"


def save_cartographer_graph(mapper: CartographerMapper, path: str | PathLike[str]) -> Path:
    """Cartographer's graph as `btnav slam --lua` leaves it (the role of its `.pbstream`):
    each node's stamp, odometry, local and optimised pose, the node each submap's frame
    hangs on, and the edges. For looking at, not for `mode: localization`, which loads
    slam_toolbox's graphs."""
    out = Path(path)
    nodes = mapper.scans
    anchors = sorted(mapper.anchors.items())
    graph = {f"graph_{k}": v for k, v in mapper.graph.to_arrays().items()}
    np.savez_compressed(
        out,
        format=np.array(CARTOGRAPHER_FORMAT),
        stamps=np.array([node.stamp for node in nodes], float),
        odom=np.array([node.odom_pose for node in nodes], float).reshape(-1, 3),
        local=np.array([node.local_pose for node in nodes], float).reshape(-1, 3),
        submap_nodes=np.array([node for _, node in anchors], np.int64),
        loop_closures=np.array(mapper.loop_closures),
        **graph,
    )
    return out
