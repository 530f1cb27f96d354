"""MPPIController's parameters: Nav2's `FollowPath` section for nav2_mppi_controller, unchanged.

Sub-sections are named as Nav2 names them: the motion model's section by the value
of `motion_model` (`diff_drive: {plugin: mppi::DiffDriveMotionModel}`), each critic's
by its entry in `critics` (validated by that critic's own `Params`), plus
`TrajectoryValidator` and `TrajectoryVisualizer` (visualisation only: ignored).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, NamedTuple

import pydantic
from pydantic import Field, field_validator, model_validator

from ... import plugins as registry
from ...core.suggest import best_match
from ...params.schema import (
    FieldProblem,
    Names,
    ParamsModel,
    Why,
    ignored,
    named_sections,
    one_of,
    section_problem,
)
from .critic_function import NAMESPACE
from .motion_models import LEGACY_NAMES, MotionModel

DEFAULT_CRITICS = [
    "ConstraintCritic",
    "CostCritic",
    "GoalCritic",
    "GoalAngleCritic",
    "PathAlignCritic",
    "PathFollowCritic",
    "PathAngleCritic",
    "PreferForwardCritic",
]

#: `motion_model: diff_drive` with no section of that name means the matching plugin.
DEFAULT_SECTION_PLUGINS = {
    "diff_drive": "mppi::DiffDriveMotionModel",
    "omni": "mppi::OmniMotionModel",
    "ackermann": "mppi::AckermannMotionModel",
}


class MotionModelChoice(NamedTuple):
    """The `motion_model` plugin and its section's params, validated by its own `Params`."""

    cls: type[MotionModel]
    params: Any


def _motion_model(label: str, section: Any) -> MotionModelChoice:
    """The section named by `motion_model` (`{plugin: mppi::..., <its params>}`)."""
    known = registry.names("motion_model")
    if not isinstance(section, Mapping) or "plugin" not in section:
        raise FieldProblem(
            (label,), f"section '{label}' names its motion model plugin ({', '.join(known)})"
        )
    body = dict(section)
    plugin = body.pop("plugin")
    if not isinstance(plugin, str) or not registry.is_registered("motion_model", plugin):
        raise FieldProblem(
            (label, "plugin"),
            f"unknown motion model plugin {plugin!r}; known: {', '.join(known)}",
            suggestion=best_match(str(plugin), [n.replace("/", "::") for n in known]),
        )
    cls = registry.lookup("motion_model", plugin)
    try:
        return MotionModelChoice(cls, cls.Params.model_validate(body))
    except pydantic.ValidationError as exc:
        raise section_problem(exc, cls.Params, label, lambda loc: (label, *loc)) from None


class TrajectoryValidatorParams(ParamsModel):
    """mppi::DefaultOptimalTrajectoryValidator: the optimal trajectory must not collide soon."""

    plugin: one_of("mppi::DefaultOptimalTrajectoryValidator") = (  # type: ignore[valid-type]
        "mppi::DefaultOptimalTrajectoryValidator"
    )
    collision_lookahead_time: float = Field(2.0, ge=0.0)
    consider_footprint: bool = False


def critic_class(name: str) -> Any:
    """The critic class for a `critics:` entry (Nav2 adds the `mppi::critics::` namespace)."""
    full = name if "::" in name or "/" in name else NAMESPACE + name
    return registry.lookup("critic", full)


class MPPIParams(ParamsModel):
    """nav2_mppi_controller::MPPIController (FollowPath)."""

    time_steps: int = Field(56, ge=2)
    model_dt: float = Field(0.05, gt=0.0)
    batch_size: int = Field(1000, ge=1)
    iteration_count: int = Field(1, ge=1)
    temperature: float = Field(0.3, gt=0.0)
    gamma: float = Field(0.015, ge=0.0)
    vx_std: float = Field(0.2, ge=0.0)
    vy_std: float = Field(0.2, ge=0.0)
    wz_std: float = Field(0.2, ge=0.0)
    vx_max: float = Field(0.5, ge=0.0)
    vx_min: float = Field(-0.35, le=0.0)
    vy_max: float = Field(0.5, ge=0.0)
    wz_max: float = Field(1.9, ge=0.0)
    ax_max: float = Field(3.0, gt=0.0)
    ax_min: float = Field(-3.0, lt=0.0)
    ay_max: float = Field(3.0, gt=0.0)
    ay_min: float = Field(-3.0, lt=0.0)
    az_max: float = Field(3.5, gt=0.0)
    model_delay_vx: float = Field(0.0, ge=0.0)
    model_delay_vy: float = Field(0.0, ge=0.0)
    model_delay_wz: float = Field(0.0, ge=0.0)
    open_loop: bool = False
    clamp_raw_controls: bool = False
    sgf_order: int = Field(2, ge=1, le=2)
    regenerate_noises: bool = False
    retry_attempt_limit: int = Field(1, ge=0)
    motion_model: str = "diff_drive"
    motion_model_section: Any = None
    critics: Names = Field(default_factory=lambda: list(DEFAULT_CRITICS))
    critic_sections: dict[str, Any] = named_sections("critics")
    unlisted_critic_sections: dict[str, Any] = Field(
        default_factory=dict,
        json_schema_extra={
            "btnav_named_sections": "critics",
            "btnav_ignored": "a critic section not named in 'critics:' is not used (as in Nav2)",
        },
    )
    trajectory_validator: TrajectoryValidatorParams = Field(
        default_factory=TrajectoryValidatorParams, alias="TrajectoryValidator"
    )
    trajectory_visualizer: dict[str, Any] = ignored(
        reason=Why.VIZ, default_factory=dict, alias="TrajectoryVisualizer"
    )
    # Path handling (Nav2's MPPI path handler keys; btnav prunes the plan it is given).
    prune_distance: float = Field(1.7, gt=0.0)
    max_robot_pose_search_dist: float | None = Field(
        None, gt=0.0, description="m along the path; default: half the costmap's diagonal"
    )
    enforce_path_inversion: bool = False
    inversion_xy_tolerance: float = Field(0.2, ge=0.0)
    inversion_yaw_tolerance: float = Field(0.4, ge=0.0)
    transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)
    visualize: bool = ignored(False, Why.VIZ)
    publish_optimal_trajectory: bool = ignored(False, Why.VIZ)
    publish_critics_stats: bool = ignored(False, Why.VIZ)
    critic_index_to_visualize: int = ignored(0, Why.VIZ)
    reset_period: float = ignored(
        1.0, "a Humble-only key: btnav resets on each new path, as Nav2 now does"
    )
    allow_parameter_qos_overrides: bool = ignored(True, Why.QOS)

    @model_validator(mode="before")
    @classmethod
    def _gather(cls, data: Any) -> Any:
        if not isinstance(data, Mapping):
            return data
        data = _gather_critics(cls, data)
        name = data.get("motion_model", "diff_drive")
        if isinstance(name, str) and name not in LEGACY_NAMES and name not in cls.model_fields:
            out = dict(data)
            if name in out:
                out["motion_model_section"] = _motion_model(name, out.pop(name))
            elif name in DEFAULT_SECTION_PLUGINS:
                section = {"plugin": DEFAULT_SECTION_PLUGINS[name]}
                out["motion_model_section"] = _motion_model(name, section)
            else:
                sections = [str(k) for k, v in data.items() if isinstance(v, Mapping)]
                known = ", ".join(registry.names("motion_model"))
                raise FieldProblem(
                    "motion_model",
                    f"motion_model '{name}' names no section '{name}:' with its plugin "
                    f"({known}); or write one of {', '.join(LEGACY_NAMES)}",
                    suggestion=best_match(
                        name, [*sections, *DEFAULT_SECTION_PLUGINS, *LEGACY_NAMES]
                    ),
                )
            return out
        return data

    @field_validator("critic_sections", mode="after")
    @classmethod
    def _critic_params(cls, sections: dict[str, Any]) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for name, body in sections.items():
            out[name] = _validate_critic(name, body)
        return out

    @model_validator(mode="after")
    def _check(self) -> MPPIParams:
        for name in self.critics:
            if name not in self.critic_sections:
                self.critic_sections[name] = _validate_critic(name, {})
        return self

    def model_section(self) -> MotionModelChoice:
        if self.motion_model in LEGACY_NAMES:
            return _motion_model(self.motion_model, {"plugin": LEGACY_NAMES[self.motion_model]})
        assert isinstance(self.motion_model_section, MotionModelChoice)
        return self.motion_model_section


def _validate_critic(name: str, body: Any) -> Any:
    try:
        model = critic_class(name).Params
    except Exception:
        known = [
            n.split("/")[-1] for n in registry.names("critic") if n.startswith("mppi/critics/")
        ]
        raise FieldProblem(
            (name,),
            f"unknown MPPI critic '{name}'; known: {', '.join(sorted(known))}",
            suggestion=best_match(name, known),
        ) from None
    try:
        return model.model_validate(body if body is not None else {})
    except pydantic.ValidationError as exc:
        raise section_problem(exc, model, name, lambda loc: (name, *loc)) from None


def _gather_critics(cls: type[pydantic.BaseModel], data: Mapping[str, Any]) -> dict[str, Any]:
    """Move each listed critic's section into `critic_sections` (a missing section means defaults)."""
    if "critic_sections" in data:
        raise FieldProblem("critic_sections", "unknown key 'critic_sections'")
    out = dict(data)
    names = data.get("critics", DEFAULT_CRITICS)
    sections: dict[str, Any] = {}
    if isinstance(names, list):
        for name in names:
            if not isinstance(name, str):
                continue
            if name in cls.model_fields:
                raise FieldProblem("critics", f"'{name}' is a key of this section, not a critic")
            if name in out:
                sections[name] = out.pop(name)
    unlisted = {}
    for key in list(out):
        if key not in cls.model_fields and isinstance(out[key], Mapping) and _is_critic(key):
            unlisted[key] = out.pop(key)
    out["critic_sections"] = sections
    out["unlisted_critic_sections"] = unlisted
    return out


def _is_critic(name: str) -> bool:
    try:
        critic_class(name)
    except Exception:
        return False
    return True
