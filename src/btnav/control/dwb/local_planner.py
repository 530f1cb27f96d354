"""dwb_core::DWBLocalPlanner: the Dynamic Window controller, vectorised over all samples.

Each cycle: prune the plan around the robot, sample velocities in the dynamic
window, simulate every sample (one (S, T, 3) array), let every critic score all
trajectories at once, drop the illegal ones (inf: hitting a lethal/inscribed
cell, leaving the costmap, oscillating, ...) and command the sample with the
lowest weighted sum. Critic `<Name>.<key>` params are written either flat, as
ROS writes them (`PathAlign.scale: 32.0`), or as a nested section.

A section read from a params file is read as Nav2 reads it: `critics` is required and
what it leaves out takes Nav2's own defaults; `DWBParams()` in code is the documented
example (`nav2_defaults` says which is which, and why).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import pydantic
from numpy.typing import NDArray
from pydantic import Field, model_validator

from ... import plugins as registry
from ...core.errors import PluginError
from ...core.geometry import Pose2D
from ...core.messages import Path, Twist
from ...core.suggest import best_match
from ...core.yaml_io import YamlMap
from ...costmap.costmap_2d import Costmap2D
from ...params.schema import (
    FieldProblem,
    Names,
    Why,
    ignored,
    named_sections,
    one_of,
    section_problem,
)
from ...plugins import register
from ..controller import Controller
from ..exceptions import InvalidPath, NoValidControl
from ..path_handler import closest_index, integrated_index
from . import critics as _critics  # noqa: F401  (registers the built-in critics)
from .critic import Trajectories, TrajectoryCritic
from .kinematic_parameters import KinematicParameters
from .nav2_defaults import DOCUMENTED_CRITICS, NAV2_CODE_DEFAULTS, missing_critics, no_motion_reason
from .trajectory_generator import sample_velocities, simulate

#: The documented critic list (docs.nav2.org's DWB example): a section built in code
#: without `critics` gets it, with the example's keys for each (`DOCUMENTED_CRITICS`).
DEFAULT_CRITICS = list(DOCUMENTED_CRITICS)


def critic_class(name: str, section: Mapping[str, Any] | None = None) -> type[TrajectoryCritic]:
    """Nav2's resolution: `<Name>.class` if given; a bare name gets `dwb_critics::` (and `Critic`)."""
    cls_name = str((section or {}).get("class", name))
    candidates = [cls_name]
    if "::" not in cls_name and "/" not in cls_name:
        candidates = [f"dwb_critics::{cls_name}", f"dwb_critics::{cls_name}Critic"]
    for c in candidates:
        if registry.is_registered("critic", c):
            return registry.lookup("critic", c)  # type: ignore[no-any-return]
    return registry.lookup("critic", candidates[0])  # raises with close names


class DWBParams(Controller.Params):
    critics: Names = Field(default_factory=lambda: list(DEFAULT_CRITICS))
    critic_params: dict[str, Any] = Field(default_factory=dict)
    unlisted_critic_params: dict[str, Any] = named_sections(
        "critics", "a critic not named in 'critics:' is not used (as in Nav2)"
    )
    trajectory_generator_name: one_of(  # type: ignore[valid-type]
        "dwb_plugins::StandardTrajectoryGenerator",
        "dwb_plugins::LimitedAccelGenerator",
        "dwb_plugins/StandardTrajectoryGenerator",
        "dwb_plugins/LimitedAccelGenerator",
    ) = "dwb_plugins::StandardTrajectoryGenerator"
    # Kinematics (dwb_plugins::KinematicParameters). These defaults are the documented
    # example's, for a section built in code; one read from a params file takes Nav2's own
    # for a key it leaves out (0.0: `nav2_defaults`). A holonomic base strafes with
    # min_vel_y < 0 < max_vel_y and acc_lim_y, decel_lim_y set; max_speed_xy caps
    # hypot(vx, vy) (negative: no cap).
    min_vel_x: float = 0.0
    min_vel_y: float = 0.0
    max_vel_x: float = 0.26
    max_vel_y: float = 0.0
    max_vel_theta: float = Field(1.0, ge=0.0)
    min_speed_xy: float = 0.0
    max_speed_xy: float = 0.26
    min_speed_theta: float = 0.0
    acc_lim_x: float = 2.5
    acc_lim_y: float = 0.0
    acc_lim_theta: float = 3.2
    decel_lim_x: float = -2.5
    decel_lim_y: float = 0.0
    decel_lim_theta: float = -3.2
    # Sampling (dwb_plugins::XYThetaIterator): per axis, a window wider than 1e-5 gets
    # max(2, samples) velocities (0 or 1 as Nav2 reads them), plus zero where it straddles it.
    vx_samples: int = Field(20, ge=0)
    vy_samples: int = Field(5, ge=0)
    vtheta_samples: int = Field(20, ge=0)
    # Simulation (dwb_plugins::StandardTrajectoryGenerator).
    sim_time: float = Field(1.7, gt=0.0)
    discretize_by_time: bool = False
    time_granularity: float = Field(0.5, gt=0.0)
    linear_granularity: float = Field(0.05, gt=0.0)  # Nav2's code: 0.5, the example's: 0.05
    angular_granularity: float = Field(0.025, gt=0.0)
    include_last_point: bool = True
    limit_vel_cmd_in_traj: bool = ignored(False, "btnav commands the sampled velocity")
    # Goal handling (read by RotateToGoal, as Nav2's critics read them from the plugin section).
    xy_goal_tolerance: float = Field(0.25, ge=0.0)
    trans_stopped_velocity: float = Field(0.25, ge=0.0)
    path_length_tolerance: float = Field(1.0, ge=0.0)
    stateful: bool = ignored(True, "goal checking is the goal checker's job in btnav")
    # Plan pruning (DWB's own, from before Nav2's path handler).
    prune_plan: bool = True
    prune_distance: float = Field(2.0, gt=0.0)
    forward_prune_distance: float = Field(2.0, gt=0.0)
    shorten_transformed_plan: bool = True
    short_circuit_trajectory_evaluation: bool = ignored(
        True, "btnav scores every trajectory at once (vectorised); the choice is the same"
    )
    default_critic_namespaces: list[str] = ignored([], "critics are found by their Nav2 names")
    debug_trajectory_details: bool = ignored(False, Why.VIZ)
    publish_evaluation: bool = ignored(True, Why.VIZ)
    publish_global_plan: bool = ignored(True, Why.VIZ)
    publish_transformed_plan: bool = ignored(True, Why.VIZ)
    publish_local_plan: bool = ignored(True, Why.VIZ)
    publish_trajectories: bool = ignored(True, Why.VIZ)
    publish_cost_grid_pc: bool = ignored(False, Why.VIZ)
    marker_lifetime: float = ignored(0.1, Why.VIZ)
    transform_tolerance: float = ignored(0.2, Why.TF)

    @model_validator(mode="before")
    @classmethod
    def _gather_critics(cls, data: Any) -> Any:
        """Each listed critic's keys, flat (`PathAlign.scale`) or nested, into its own Params;
        a problem names the key as the file writes it.

        A section read from a params file (the loader hands a `YamlMap`) is read as Nav2
        reads it: `critics` is required and a key left out takes Nav2's own default; one
        built in code gets the documented example for what it leaves out (`nav2_defaults`).
        """
        if not isinstance(data, Mapping):
            return data
        for internal in ("critic_params", "unlisted_critic_params"):
            if internal in data:
                raise FieldProblem(internal, f"unknown key '{internal}'")
        from_file = isinstance(data, YamlMap)
        if from_file and not data.get("critics"):
            raise missing_critics(data)
        documented = "critics" not in data
        names = data.get("critics", DEFAULT_CRITICS)
        if not isinstance(names, list):
            return data
        out: dict[str, Any] = {}
        #: per critic: its key -> (value, the key's path in the file)
        sections: dict[str, dict[str, tuple[Any, tuple[str, ...]]]] = {
            n: {} for n in names if isinstance(n, str)
        }
        unlisted: dict[str, Any] = {}
        for key, value in data.items():
            head, dot, tail = str(key).partition(".")
            nested = isinstance(value, Mapping) and not dot
            if dot and head in sections:
                sections[head][tail] = (value, (key,))
            elif nested and head in sections:
                sections[head].update({str(k): (v, (key, str(k))) for k, v in value.items()})
            elif (dot or nested) and head not in cls.model_fields and _is_critic(head):
                # a critic the list leaves out: its keys are not used (as in Nav2)
                unlisted.setdefault(head, {}).update({tail: value} if dot else value)
            elif dot or (nested and head not in cls.model_fields):
                raise FieldProblem(
                    head if nested else key,
                    f"'{head}' is neither a key of this section nor a critic in its list "
                    f"({', '.join(sections)})",
                    suggestion=best_match(head, [*sections, *cls.model_fields]),
                )
            else:
                out[key] = value
        if from_file:
            out = {**NAV2_CODE_DEFAULTS, **out}
        out["unlisted_critic_params"] = unlisted
        out["critic_params"] = {
            name: _critic_params(name, keys, documented) for name, keys in sections.items()
        }
        return out


def _critic_params(
    name: str, keys: dict[str, tuple[Any, tuple[str, ...]]], documented: bool
) -> Any:
    """The critic's Params from its keys. What they leave out is the critic's own default
    (Nav2's: scale 1.0, forward_point_distance 0.325, ...), or with `documented` (the
    section built in code without a list) the documented example's value."""
    raw = {k: value for k, (value, _) in keys.items()}
    try:
        cls = critic_class(name, raw)
    except PluginError as exc:
        where = keys["class"][1] if "class" in keys else ("critics",)
        raise FieldProblem(where, exc.message, suggestion=exc.suggestion) from None
    raw.pop("class", None)
    if documented:
        raw = {**DOCUMENTED_CRITICS.get(name, {}), **raw}
    try:
        return cls.Params.model_validate(raw)
    except pydantic.ValidationError as exc:

        def place(loc: tuple[str, ...]) -> tuple[str, ...]:
            return keys[loc[0]][1] if loc and loc[0] in keys else ("critics",)

        raise section_problem(exc, cls.Params, f"critic {name}", place) from None


def _is_critic(name: str) -> bool:
    try:
        critic_class(name)
    except PluginError:
        return False
    return True


#: The documented example's limits (DWBParams' defaults), named by the no-motion message.
_DOCUMENTED_LIMITS = {k: float(DWBParams.model_fields[k].default) for k in NAV2_CODE_DEFAULTS}


@register("controller", "dwb_core::DWBLocalPlanner")
class DWBLocalPlanner(Controller):
    Params = DWBParams
    params: DWBParams

    def __init__(self, name: str = "FollowPath", params: DWBParams | None = None) -> None:
        super().__init__(name, params)
        self.critics: list[TrajectoryCritic] = []
        for cname in self.params.critics:
            cls = critic_class(cname)
            self.critics.append(cls(cname, self.params.critic_params[cname], self.params))
        #: The section's limits, and those a speed limit leaves (Nav2's KinematicsHandler).
        self.base_kinematics = KinematicParameters.from_params(self.params)
        self.kinematics = self.base_kinematics
        self._plan = np.zeros((0, 3))
        self.control_duration = 0.05
        self.last_trajectories: Trajectories | None = None
        self.last_scores: NDArray[np.float64] | None = None

    def configure(self, costmap_ros: Any) -> None:
        """As Nav2's DWB initialises each critic with the costmap server."""
        super().configure(costmap_ros)
        for c in self.critics:
            c.configure(costmap_ros)

    def set_plan(self, path: Path) -> None:
        poses = np.asarray(path.poses, float).reshape(-1, 3)
        if len(poses) == 0:
            raise InvalidPath("Received plan with zero length")
        self._plan = poses
        for c in self.critics:
            c.reset()

    def refresh_plan(self, path: Path) -> None:
        """The same plan after `map -> odom` moved: the critics keep their state."""
        poses = np.asarray(path.poses, float).reshape(-1, 3)
        if len(poses) == 0:
            raise InvalidPath("Received plan with zero length")
        self._plan = poses

    def reset(self) -> None:
        for c in self.critics:
            c.reset()

    def local_plan(self, pose: Pose2D) -> np.ndarray | None:
        """The best-scored trajectory of the last cycle (DWB's local plan); empty when
        every trajectory was illegal."""
        trajs, scores = self.last_trajectories, self.last_scores
        if trajs is None or scores is None or not len(scores):
            return np.zeros((0, 3))
        best = int(np.argmin(scores))
        if not math.isfinite(scores[best]):
            return np.zeros((0, 3))
        return np.asarray(trajs.poses[best], dtype=float).reshape(-1, 3)

    def set_speed_limit(self, speed_limit: float, percentage: bool) -> None:
        """Nav2's KinematicsHandler::setSpeedLimit, from the section's own limits."""
        self.kinematics = self.base_kinematics.with_speed_limit(speed_limit, percentage)

    @property
    def max_vel_x(self) -> float:
        """The forward speed the current speed limit allows."""
        return self.kinematics.max_vel_x

    def _local_plan(self, pose: Pose2D, costmap: Costmap2D) -> NDArray[np.float64]:
        p = self.params
        if len(self._plan) == 0:
            raise InvalidPath("Received plan with zero length")
        extent = max(costmap.size_in_meters) / 2.0
        closest = closest_index(self._plan, pose.x, pose.y, max(p.prune_distance, extent))
        if p.prune_plan:
            self._plan = self._plan[closest:]
            closest = 0
        end = integrated_index(self._plan, closest, p.forward_prune_distance)
        if not p.shorten_transformed_plan:
            end = len(self._plan)
        local = self._plan[closest:end]
        _, inside = costmap.world_to_map(local[:, :2])
        off = np.flatnonzero(~inside)
        if off.size:
            local = local[: max(int(off[0]), 1)]
        return local

    def compute_velocity_commands(
        self, pose: Pose2D, velocity: Twist, costmap: Costmap2D, goal_checker: Any = None
    ) -> Twist:
        p = self.params
        plan = self._local_plan(pose, costmap)
        goal = Pose2D.from_array(self._plan[-1])
        for c in self.critics:
            if not c.prepare(pose, velocity, goal, plan, costmap):
                raise NoValidControl(f"A scoring function ({c.name}) failed to prepare")
        limited = p.trajectory_generator_name.endswith("LimitedAccelGenerator")
        acc_time = self.control_duration if limited else p.sim_time
        kin = self.kinematics
        counts = (p.vx_samples, p.vy_samples, p.vtheta_samples)
        samples = sample_velocities(kin, counts, velocity, acc_time)
        if len(samples) == 0:
            raise NoValidControl(
                "No valid velocity samples in the dynamic window"
                + no_motion_reason(kin, _DOCUMENTED_LIMITS)
            )
        trajs = simulate(p, kin, pose, velocity, samples, limited)
        total = np.zeros(len(samples))
        for c in self.critics:
            scale = c.get_scale(costmap)
            raw = c.score(trajs, costmap)
            illegal = ~np.isfinite(raw)
            total = np.where(illegal, np.inf, total + scale * np.where(illegal, 0.0, raw))
        self.last_trajectories, self.last_scores = trajs, total
        best = int(np.argmin(total))
        if not math.isfinite(total[best]):
            raise NoValidControl(f"No valid trajectories out of {len(samples)}!")
        v = samples[best]
        cmd = Twist(linear_x=float(v[0]), linear_y=float(v[1]), angular_z=float(v[2]))
        for c in self.critics:
            c.debrief(cmd, pose)
        return cmd


__all__ = ["DEFAULT_CRITICS", "DOCUMENTED_CRITICS", "DWBLocalPlanner", "DWBParams"]
