"""The navigation stack a Nav2 launch brings up, built from one params file on a runtime.

`NavStack.build(runtime, params, map_grid, seed=...)` creates, from the params file as
Nav2 writes it: map_server (the mission's map, else `yaml_filename`), the global
costmap (in `map`, static + obstacle + inflation for Nav2's file) and the local
costmap (rolling in `odom`) as components at their `update_frequency`, and the
planner, controller, smoother and behavior servers with their actions
(`compute_path_to_pose`, `compute_path_through_poses`, `follow_path`,
`smooth_path`, `spin`, `backup`, `drive_on_heading`, `wait`), and explore's frontier
services (`explore/compute_frontiers`, `explore/blacklist_frontier`). The localiser
(`runtime.use_localizer`) is the mission's choice and is added by its owner.

`stack.set_parameters("local_costmap", {"inflation_layer.inflation_radius": 0.5})`
is Nav2's dynamic parameters: validated like the file (`params.validate_update`;
nothing changes if one value is wrong) and applied to the running server.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from os import PathLike
from typing import Any

from ..costmap.costmap_ros import CostmapROS
from ..maps.occupancy_grid import OccupancyGrid
from ..params.loader import load_params
from ..params.paramsfile import ParamsFile, ServerParams
from ..params.updates import validate_update
from .behavior_server import BehaviorServer
from .collision_monitor_server import CollisionDetectorServer, CollisionMonitorServer
from .controller_server import ControllerServer
from .costmap_filter_servers import bring_up_costmap_filters
from .costmap_server import CostmapServer
from .docking_server import DockingServer
from .explore_server import ExploreServer
from .map_server import MapServer
from .planner_server import PlannerServer
from .route_server import bring_up_route_server
from .runtime import Runtime
from .smoother_server import SmootherServer
from .velocity_smoother import VelocitySmoother


class NavStack:
    def __init__(
        self,
        runtime: Runtime,
        params: ParamsFile,
        map_server: MapServer,
        global_costmap: CostmapServer,
        local_costmap: CostmapServer,
        planner_server: PlannerServer,
        controller_server: ControllerServer,
        smoother_server: SmootherServer,
        behavior_server: BehaviorServer,
        explore_server: ExploreServer,
    ) -> None:
        self.runtime = runtime
        self.params = params
        self.map_server = map_server
        self.global_costmap = global_costmap
        self.local_costmap = local_costmap
        self.planner_server = planner_server
        self.controller_server = controller_server
        self.smoother_server = smoother_server
        self.behavior_server = behavior_server
        self.explore_server = explore_server
        #: The command chain's servers, when the params file brings them up.
        self.velocity_smoother: VelocitySmoother | None = None
        self.collision_monitor: CollisionMonitorServer | None = None
        #: Servers by their params-file name, for set_parameters.
        self.servers: dict[str, Any] = {
            "global_costmap": global_costmap,
            "local_costmap": local_costmap,
            "planner_server": planner_server,
            "controller_server": controller_server,
            "smoother_server": smoother_server,
            "behavior_server": behavior_server,
            "explore": explore_server,
        }

    @classmethod
    def build(
        cls,
        runtime: Runtime,
        params: ParamsFile | str | PathLike[str],
        map_grid: OccupancyGrid | None = None,
        *,
        seed: int | None = None,
    ) -> NavStack:
        """Every server of the params file on `runtime`; `seed` defaults to the runtime's."""
        seed = runtime.seed if seed is None else seed
        pf = params if isinstance(params, ParamsFile) else load_params(params)
        map_server = MapServer(pf.server("map_server").model, map=map_grid, base_dir=pf.path.parent)
        global_ros = CostmapROS.from_params(pf, "global_costmap")
        map_server.subscribe(global_ros.set_map)
        global_costmap = runtime.add(CostmapServer(runtime, global_ros))
        local_costmap = runtime.add(
            CostmapServer(runtime, CostmapROS.from_params(pf, "local_costmap"))
        )
        planner = runtime.add(
            PlannerServer(runtime, pf.server("planner_server"), global_costmap, seed=seed)
        )
        controller = runtime.add(
            ControllerServer(runtime, pf.server("controller_server"), local_costmap, seed=seed)
        )
        smoother = runtime.add(
            SmootherServer(runtime, pf.server("smoother_server"), global_costmap, seed=seed)
        )
        behaviors = BehaviorServer(
            runtime,
            pf.server("behavior_server"),
            local_costmap=local_costmap,
            global_costmap=global_costmap,
        )
        explore = ExploreServer(runtime, pf.server("explore"), global_costmap, map_server)
        stack = cls(
            runtime,
            pf,
            map_server,
            global_costmap,
            local_costmap,
            planner,
            controller,
            smoother,
            behaviors,
            explore,
        )
        # The servers Nav2's launch brings up beside these, each only when the params
        # file has its section (a file without one runs as before), in launch order.
        bring_up_costmap_filters(stack)
        bring_up_route_server(stack)
        stack.bring_up_cmd_vel_chain()
        if "docking_server" in pf:  # its cmd_vel goes to the base, not down the chain
            docking = DockingServer(
                runtime, pf.server("docking_server"), local_costmap, base_dir=pf.path.parent
            )
            stack.add_server("docking_server", runtime.add(docking))
        return stack

    def bring_up_cmd_vel_chain(self) -> None:
        """nav2_bringup's command chain: the servers' `cmd_vel_nav` -> velocity_smoother ->
        `cmd_vel_smoothed` -> collision_monitor -> the base's `cmd_vel`, each stage only
        when its section is in the file. The smoother is added after the servers, so it
        ticks in the step a command is sent; the monitor acts on each command it gets.
        collision_detector watches its zones beside the chain and never acts."""
        runtime, pf = self.runtime, self.params
        to_base = runtime.command_base
        if "collision_monitor" in pf:
            monitor = CollisionMonitorServer(
                runtime, pf.server("collision_monitor"), self.local_costmap, publish=to_base
            )
            self.collision_monitor = self.add_server("collision_monitor", monitor)
            to_base = monitor.command_received
        if "velocity_smoother" in pf:
            smoother = VelocitySmoother(runtime, pf.server("velocity_smoother"), publish=to_base)
            self.velocity_smoother = self.add_server("velocity_smoother", runtime.add(smoother))
            runtime.route_cmd_vel(smoother.command_received)
        else:
            runtime.route_cmd_vel(to_base)
        if "collision_detector" in pf:
            detector = CollisionDetectorServer(
                runtime, pf.server("collision_detector"), self.local_costmap
            )
            self.add_server("collision_detector", runtime.add(detector))

    def add_server(self, name: str, server: Any) -> Any:
        """Keep an optional server under its params-file name (for set_parameters); returns it."""
        self.servers[name] = server
        return server

    # -- dynamic parameters ---------------------------------------------------------------

    def set_parameters(self, server: str, changes: Mapping[str, Any]) -> ServerParams:
        """Change a running server's params, validated like the file; returns its new params."""
        updated = validate_update(self.params, server, changes)
        target = self.servers.get(updated.name)
        if target is not None:
            target.set_parameters(updated)
        return updated

    # -- services -------------------------------------------------------------------------

    def services(self) -> dict[str, Callable[..., Any]]:
        """Nav2's service names -> callables (clear costmaps, load_map, and the localiser's
        reinitialize_global_localization and request_nomotion_update when it has them)."""
        out: dict[str, Callable[..., Any]] = {}
        out.update(self.global_costmap.services())
        out.update(self.local_costmap.services())
        out["map_server/load_map"] = self.map_server.load_map
        for name in ("collision_monitor", "route_server"):
            server = self.servers.get(name)
            if server is not None:
                out.update(server.services())
        out.update(self.explore_server.services())
        localizer = self.runtime.localizer
        for name in ("reinitialize_global_localization", "request_nomotion_update"):
            service = getattr(localizer, name, None)
            if service is not None:  # amcl's services
                out[name] = service
        return out

    def clear_all_costmaps(self) -> None:
        self.global_costmap.costmap_ros.clear_entirely()
        self.local_costmap.costmap_ros.clear_entirely()
