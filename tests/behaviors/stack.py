"""A small stack for behaviour tests: world, runtime with ground truth, local costmap, server."""

from __future__ import annotations

import copy
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from btnav.core.resources import bundled_dir
from btnav.core.yaml_io import load_yaml
from btnav.costmap import CostmapROS
from btnav.nav import Runtime, Stage
from btnav.nav.behavior_server import BehaviorServer
from btnav.params import load_params
from btnav.params.loader import load_params_doc
from btnav.sim.world import World

OFFICE = bundled_dir("worlds") / "small_office.yaml"
NAV2_PARAMS = bundled_dir("params") / "nav2_params.yaml"


class LocalCostmapNode:
    """local_costmap on the schedule: takes every scan, updates at update_frequency."""

    stage = Stage.COSTMAP

    def __init__(self, runtime: Runtime, costmap: CostmapROS) -> None:
        self.runtime = runtime
        self.costmap = costmap
        self.rate = costmap.params.update_frequency
        self._scans: list[Any] = []
        runtime.subscribe("scan", self._scans.append)

    def update(self, now: float) -> None:
        self.costmap.update(scans=self._scans, frame_tree=self.runtime.frames, now=now, force=True)
        self._scans.clear()


@dataclass
class Stack:
    runtime: Runtime
    costmap: CostmapROS
    server: BehaviorServer

    @property
    def world(self) -> World:
        return self.runtime.world

    def send(self, name: str, goal: Any) -> Any:
        return self.runtime.action_client(name).send_goal(goal)

    def run(self, handle: Any, timeout: float = 30.0) -> Any:
        assert self.runtime.run_until(lambda: handle.done, timeout), f"{handle} did not finish"
        return handle


def make_stack(world: World, params: Any = None) -> Stack:
    params = params if params is not None else load_params(NAV2_PARAMS)
    rt = Runtime(world, seed=0)
    rt.use_localizer("ground_truth")
    costmap = CostmapROS.from_params(params, "local_costmap")
    rt.add(LocalCostmapNode(rt, costmap))
    server = BehaviorServer(rt, params, local_costmap=costmap)
    rt.spin_for(0.5)  # the costmap has seen a few scans
    return Stack(rt, costmap, server)


def nav2_doc() -> dict[str, Any]:
    """Nav2's params file as plain data, to edit a copy of."""
    return copy.deepcopy(_to_plain(load_yaml(NAV2_PARAMS)))


def _to_plain(node: Any) -> Any:
    if isinstance(node, dict):
        return {k: _to_plain(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_to_plain(v) for v in node]
    return node


def params_from(doc: dict[str, Any], tmp_path: Path) -> Any:
    return load_params_doc(doc, tmp_path / "params.yaml")


def write_world(tmp_path: Path, text: str) -> World:
    path = tmp_path / "world.yaml"
    path.write_text(text)
    return World.from_file(path, seed=0)
