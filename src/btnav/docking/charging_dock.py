"""The dock plugin interface (plugin kind `charging_dock`), opennav_docking_core's ChargingDock.

A dock plugin knows one type of dock: where its staging pose is, how to refine the
dock's pose from detections, whether the robot is docked and charging. The docking
server builds each plugin named in `dock_plugins` as every plugin is built,
`cls(name, params)`, then `configure(context)` hands it what it reads the world through:
the frame tree (`context.lookup(target, source)`), sim time (`context.now`) and the
server's `base_frame`. Detections reach it through `on_detected_dock_pose` (Nav2's
`detected_dock_pose` subscription). `NonChargingDock` is a dock that does not charge
(Nav2's NonChargingDock): asking it about charging is a programming error.
"""

from __future__ import annotations

from enum import Enum
from typing import Any, Protocol

from ..core.geometry import Pose2D
from ..core.messages import PoseStamped
from ..core.nav2_docking_msgs import PoseStamped3D
from ..plugins import Plugin


class DockDirection(str, Enum):
    """opennav_docking_core::DockDirection: which way the robot drives onto the dock."""

    FORWARD = "forward"
    BACKWARD = "backward"


class DockContext(Protocol):
    """What the docking server gives its dock plugins (a node, tf buffer and clock in Nav2)."""

    base_frame: str

    @property
    def now(self) -> float: ...

    def lookup(self, target: str, source: str) -> Pose2D: ...


class ChargingDock(Plugin):
    """Base of the dock plugins (`@register("charging_dock", name)`)."""

    context: Any = None

    def configure(self, context: DockContext) -> None:  # type: ignore[override]
        """Once, after construction: what the plugin reads frames and time through."""
        self.context = context

    # -- staging and perception -------------------------------------------------------

    def get_staging_pose(self, pose: Pose2D, frame: str) -> PoseStamped:
        """Where the robot goes before its approach, for a dock at `pose` in `frame`."""
        raise NotImplementedError

    def get_refined_pose(self, pose: PoseStamped, dock_id: str = "") -> PoseStamped | None:
        """The dock's pose refined by perception (in `pose`'s frame; `pose` is the estimate),
        or None when no usable detection is there."""
        raise NotImplementedError

    def on_detected_dock_pose(self, msg: PoseStamped3D) -> None:
        """A detection (`detected_dock_pose`); plugins that use none ignore it."""

    def start_detection_process(self) -> bool:
        """Turn the detector on (before the initial perception); False if it failed."""
        return True

    def stop_detection_process(self) -> bool:
        """Turn the detector off (after docking, failed or not)."""
        return True

    # -- state ------------------------------------------------------------------------

    @property
    def is_charger(self) -> bool:
        return True

    def is_docked(self) -> bool:
        raise NotImplementedError

    def is_charging(self) -> bool:
        raise NotImplementedError

    def disable_charging(self) -> bool:
        """Stop charging before undocking; True once it may drive off."""
        raise NotImplementedError

    def has_stopped_charging(self) -> bool:
        raise NotImplementedError

    @property
    def dock_direction(self) -> DockDirection:
        return DockDirection.FORWARD

    def should_rotate_to_dock(self) -> bool:
        """Turn 180 degrees at the staging pose before a backward approach (rotate_to_dock)."""
        return False


class NonChargingDock(ChargingDock):
    """A dock without charging (opennav_docking_core::NonChargingDock)."""

    @property
    def is_charger(self) -> bool:
        return False

    def is_charging(self) -> bool:
        raise RuntimeError("is_charging does not apply to a non-charging dock")

    def disable_charging(self) -> bool:
        raise RuntimeError("disable_charging does not apply to a non-charging dock")

    def has_stopped_charging(self) -> bool:
        raise RuntimeError("has_stopped_charging does not apply to a non-charging dock")
