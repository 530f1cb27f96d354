"""Keys every Nav2 node accepts (ROS and nav2::LifecycleNode plumbing), all ignored by btnav."""

from __future__ import annotations

from typing import Any

from .schema import ParamsModel, Why, ignored, one_of

IntrospectionMode = one_of("disabled", "metadata", "contents")


class NodeParams(ParamsModel):
    """Base of every server model: the keys any Nav2 lifecycle node declares."""

    use_sim_time: bool = ignored(False, Why.SIM_TIME)
    introspection_mode: IntrospectionMode = ignored("disabled", Why.ROS)
    bond_heartbeat_period: float = ignored(0.25, Why.ROS, ge=0.0)
    bond_disable_heartbeat_timeout: bool = ignored(True, Why.ROS)
    autostart_node: bool = ignored(False, Why.ROS)
    allow_parameter_qos_overrides: bool = ignored(True, Why.ROS)
    qos_overrides: dict[str, Any] | None = ignored(None, Why.ROS)
    warn_on_missing_params: bool = ignored(False, Why.ROS)
    strict_param_loading: bool = ignored(False, Why.ROS)
    enable_stamped_cmd_vel: bool = ignored(
        True, "btnav's velocity commands are plain Twist messages"
    )
