"""slam_toolbox's SerializePoseGraph / DeserializePoseGraph, as one `.npz` file.

The file holds the pose graph (nodes, edges, information matrices) and every processed
scan (stamp, odometry pose, readings, points), so a later run can localise against it
(`mode: localization`) or continue mapping. It is numpy's `.npz` with no pickled
objects: loading it runs no code (`allow_pickle=False`).
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path

import numpy as np

from ...core.errors import BtnavError
from ...params.localization import SlamToolboxParams
from ..graph.pose_graph import PoseGraph
from .mapper import Mapper, Scan

FORMAT = "btnav-pose-graph-1"


class PoseGraphFileError(BtnavError):
    """A serialised pose graph that cannot be read."""


def graph_file(path: str | PathLike[str]) -> Path:
    """slam_toolbox names a serialised graph without its extension; btnav's is `.npz`."""
    p = Path(path)
    return p if p.suffix == ".npz" else p.with_name(p.name + ".npz")


def _ragged(parts: list[np.ndarray], dtype: type) -> tuple[np.ndarray, np.ndarray]:
    lengths = np.array([len(p) for p in parts], np.int64)
    flat = np.concatenate(parts).astype(dtype) if parts else np.zeros(0, dtype)
    return flat, np.concatenate([[0], np.cumsum(lengths)])


def save_pose_graph(mapper: Mapper, path: str | PathLike[str]) -> Path:
    out = Path(path)
    scans = mapper.scans
    points, point_at = _ragged([s.points.reshape(-1, 2) for s in scans], np.float64)
    ranges, range_at = _ragged([s.ranges for s in scans], np.float32)
    angles, _ = _ragged([s.angles for s in scans], np.float64)
    graph = {f"graph_{k}": v for k, v in mapper.graph.to_arrays().items()}
    np.savez_compressed(
        out,
        format=np.array(FORMAT),
        start=mapper.start,
        stamps=np.array([s.stamp for s in scans], float),
        odom=np.array([s.odom_pose for s in scans], float).reshape(-1, 3),
        centroids=np.array([s.centroid for s in scans], float).reshape(-1, 2),
        points=points.reshape(-1, 2),
        point_at=point_at,
        ranges=ranges,
        angles=angles,
        range_at=range_at,
        running=np.array(mapper.running, np.int64),
        loop_closures=np.array(mapper.loop_closures),
        **graph,
    )
    return out


def load_pose_graph(
    path: str | PathLike[str], params: SlamToolboxParams, into: Mapper | None = None
) -> Mapper:
    """slam_toolbox's DeserializePoseGraph: the graph and its scans, into a new `Mapper`
    (started where the file's was) or into `into` (a mapper that goes on mapping)."""
    src = Path(path)
    try:
        with np.load(src, allow_pickle=False) as z:
            if "format" not in z or str(z["format"]) != FORMAT:
                raise PoseGraphFileError("not a btnav pose graph file", file=src)
            d = {k: z[k] for k in z.files}
    except (OSError, ValueError) as err:
        raise PoseGraphFileError(f"cannot read the pose graph: {err}", file=src) from None
    mapper = into if into is not None else Mapper(params, d["start"])
    mapper.graph = PoseGraph.from_arrays(
        {k.removeprefix("graph_"): v for k, v in d.items() if k.startswith("graph_")}
    )
    pa, ra = d["point_at"], d["range_at"]
    mapper.scans = [
        Scan(
            float(d["stamps"][i]),
            d["odom"][i],
            d["points"][pa[i] : pa[i + 1]],
            d["ranges"][ra[i] : ra[i + 1]],
            d["angles"][ra[i] : ra[i + 1]],
            d["centroids"][i],
        )
        for i in range(len(d["stamps"]))
    ]
    mapper.running = [int(i) for i in d["running"]]
    mapper.loop_closures = int(d["loop_closures"])
    return mapper
