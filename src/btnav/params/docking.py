"""Keys of Nav2's docking_server (opennav_docking): the server, its controller, its docks.

The dock plugin sections (`dock_plugins: [simple_charging_dock]`, then
`simple_charging_dock: {plugin: ...}`) are resolved by the loader as every plugin list
is. Dock instances are named by `docks: [home_dock]`, each a section with `type` (a
name in `dock_plugins`), `frame` (default map), `pose: [x, y, yaw]` and an optional
`id`; or they come from a `dock_database:` file (Nav2's dock file, relative to the
params file; `docking.dock_database.load_dock_file`), which then wins, as in Nav2. The
approach controller is the `controller:` sub-section (Nav2's graceful control law).
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import AfterValidator, Field, model_validator

from ..core.suggest import best_match
from .node import NodeParams
from .schema import FieldProblem, Frame, Names, ParamsModel, Why, gather_sections, ignored
from .schema import named_sections as _named_sections

_ODOM = "btnav's docking server reads the odometry's latest twist (no smoothing window)"


def _pose3(v: list[float]) -> list[float]:
    if len(v) != 3:
        raise ValueError(f"a dock pose is [x, y, yaw], got {len(v)} numbers")
    return v


DockPose = Annotated[list[float], AfterValidator(_pose3)]


class DockInstance(ParamsModel):
    """One dock of the database: where it is and which plugin docks at it."""

    type: str = Field(min_length=1, description="a name listed in dock_plugins")
    frame: Frame = "map"
    pose: DockPose
    id: str = ""


class DockingControllerParams(ParamsModel):
    """`controller:`: the graceful control law that drives the approach, and its collision check."""

    k_phi: float = Field(3.0, ge=0.0)
    k_delta: float = Field(2.0, ge=0.0)
    beta: float = Field(0.4, ge=0.0)
    lambda_: float = Field(2.0, ge=0.0, alias="lambda")
    v_linear_min: float = Field(0.1, ge=0.0)
    v_linear_max: float = Field(0.25, gt=0.0)
    v_angular_max: float = Field(0.75, gt=0.0)
    slowdown_radius: float = Field(0.25, gt=0.0)
    deceleration_max: float = Field(2.5, gt=0.0)
    rotate_to_heading_angular_vel: float = Field(1.0, gt=0.0)
    rotate_to_heading_max_angular_accel: float = Field(3.2, gt=0.0)
    use_collision_detection: bool = True
    projection_time: float = Field(5.0, ge=0.0)
    simulation_time_step: float = Field(0.1, gt=0.0)
    dock_collision_threshold: float = Field(0.3, ge=0.0)
    costmap_topic: str = ignored(
        "local_costmap/costmap_raw", "btnav's docking server checks the local costmap directly"
    )
    footprint_topic: str = ignored("local_costmap/published_footprint", Why.TOPIC)
    transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)
    simulation_step: float = ignored(
        0.1,
        "nav2_params.yaml writes it, but Nav2's docking controller reads "
        "simulation_time_step: Nav2 does not read this key either",
    )

    @model_validator(mode="after")
    def _speeds(self) -> DockingControllerParams:
        if self.v_linear_min > self.v_linear_max:
            raise FieldProblem(
                "v_linear_min",
                f"v_linear_min ({self.v_linear_min}) is above v_linear_max ({self.v_linear_max})",
            )
        return self


class DockingServerParams(NodeParams):
    """docking_server: docks and undocks the robot (DockRobot, UndockRobot)."""

    controller_frequency: float = Field(50.0, gt=0.0)
    initial_perception_timeout: float = Field(5.0, ge=0.0)
    wait_charge_timeout: float = Field(5.0, ge=0.0)
    dock_approach_timeout: float = Field(30.0, ge=0.0)
    rotate_to_dock_timeout: float = Field(10.0, ge=0.0)
    undock_linear_tolerance: float = Field(0.05, ge=0.0)
    undock_angular_tolerance: float = Field(0.05, ge=0.0)
    max_retries: int = Field(3, ge=0)
    base_frame: Frame = "base_link"
    fixed_frame: Frame = "odom"
    dock_prestaging_tolerance: float = Field(0.5, ge=0.0)
    rotation_angular_tolerance: float = Field(0.05, ge=0.0)
    dock_backwards: bool | None = Field(
        None, description="deprecated by Nav2: set dock_direction in the dock plugin instead"
    )
    navigator_bt_xml: str = Field("", description="the staging NavigateToPose's tree; '': default")
    odom_topic: str = ignored("odom", Why.TOPIC)
    odom_duration: float = ignored(0.3, _ODOM, gt=0.0)
    dock_plugins: Names = []
    dock_database: str | None = Field(None, min_length=1)
    docks: Names = []
    dock_sections: dict[str, DockInstance] = _named_sections("docks")
    controller: DockingControllerParams = Field(default_factory=DockingControllerParams)

    @model_validator(mode="before")
    @classmethod
    def _gather(cls, data: Any) -> Any:
        return gather_sections(cls, data, "docks", "dock_sections")

    @model_validator(mode="after")
    def _dock_types(self) -> DockingServerParams:
        for name, dock in self.dock_sections.items():
            if dock.type not in self.dock_plugins:
                raise FieldProblem(
                    ("dock_sections", name, "type"),
                    f"dock '{name}' has type '{dock.type}', which is not one of dock_plugins "
                    f"({', '.join(self.dock_plugins) or 'none'})",
                    suggestion=best_match(dock.type, self.dock_plugins),
                )
        return self
