"""What opennav_docking's SimpleChargingDock and SimpleNonChargingDock share.

The staging pose is `staging_x_offset` metres along the dock's x axis from the dock
pose (negative: in front of it), turned by `staging_yaw_offset`. Without
`use_external_detection_pose` the dock's pose is its database pose; with it, each
`detected_dock_pose` (no older than `external_detection_timeout`) is taken into the
requested frame, filtered (`filter_coef`), turned by `external_detection_rotation_*`
to a ground-plane yaw and shifted by `external_detection_translation_x/y` (in the
dock's frame) to the dock pose. The robot is docked when its base frame is within
`docking_threshold` of that pose.

btnav has no joint states or detector services: `use_stall_detection` and the
`detector_service_*` keys are accepted and listed as ignored.
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BeforeValidator, Field, model_validator

from ..core import fmath
from ..core.errors import FrameError
from ..core.geometry import Pose2D
from ..core.messages import PoseStamped
from ..core.nav2_docking_msgs import PoseStamped3D
from ..core.quaternion import from_rpy, from_yaw, multiply, yaw_of
from ..params.schema import FieldProblem, ParamsModel, Why, ignored, one_of
from .charging_dock import ChargingDock, DockDirection
from .pose_filter import PoseFilter

_NO_JOINTS = "btnav has no joint states: docked is judged by docking_threshold"


def _lower(value: Any) -> Any:
    """Nav2 reads dock_direction in any case (FORWARD, Backward, ...)."""
    return value.lower() if isinstance(value, str) else value


Direction = Annotated[one_of("forward", "backward"), BeforeValidator(_lower)]


class SimpleDockParams(ParamsModel):
    docking_threshold: float = Field(0.05, gt=0.0, description="m from the dock pose = docked")
    staging_x_offset: float = -0.7
    staging_yaw_offset: float = 0.0
    use_external_detection_pose: bool = False
    external_detection_timeout: float = Field(1.0, ge=0.0)
    external_detection_translation_x: float = -0.20
    external_detection_translation_y: float = 0.0
    external_detection_rotation_yaw: float = 0.0
    external_detection_rotation_pitch: float = 1.57
    external_detection_rotation_roll: float = -1.57
    filter_coef: float = Field(0.1, le=1.0)
    dock_direction: Direction = "forward"
    rotate_to_dock: bool = False
    subscribe_toggle: bool = False
    use_stall_detection: bool = ignored(False, _NO_JOINTS)
    stall_joint_names: list[str] = ignored([], _NO_JOINTS)
    stall_velocity_threshold: float = ignored(1.0, _NO_JOINTS)
    stall_effort_threshold: float = ignored(1.0, _NO_JOINTS)
    detector_service_name: str = ignored("", Why.SERVICE)
    detector_service_timeout: float = ignored(5.0, Why.SERVICE)

    @model_validator(mode="after")
    def _rotate_needs_backward(self) -> SimpleDockParams:
        if self.rotate_to_dock and self.dock_direction != "backward":
            raise FieldProblem(
                "rotate_to_dock",
                "rotate_to_dock turns the robot round to back onto the dock: it needs "
                "dock_direction: backward (Nav2 refuses it otherwise)",
            )
        return self


class SimpleDock(ChargingDock):
    """The shared behaviour of the two simple docks (see the module doc)."""

    Params = SimpleDockParams
    params: SimpleDockParams

    def __init__(self, name: str, params: Any = None) -> None:
        super().__init__(name, params)
        p = self.params
        self.dock_pose = PoseStamped(0.0, Pose2D(), "")  # no valid dock pose yet
        self.filter = PoseFilter(p.filter_coef, p.external_detection_timeout)
        self.rotation = from_rpy(
            p.external_detection_rotation_roll,
            p.external_detection_rotation_pitch,
            p.external_detection_rotation_yaw,
        )
        self.detected: PoseStamped3D | None = None
        self.initial_pose_received = False
        self.detection_active = False
        #: Whether detections are heard: always with use_external_detection_pose, or
        #: (subscribe_toggle) only between start and stop of the detection process.
        self.subscribed = p.use_external_detection_pose and not p.subscribe_toggle
        self.staging_pose: PoseStamped | None = None

    # -- staging and perception -------------------------------------------------------

    def get_staging_pose(self, pose: Pose2D, frame: str) -> PoseStamped:
        p = self.params
        if not p.use_external_detection_pose:  # a new docking: the database pose it is
            self.dock_pose = PoseStamped(self.context.now, pose, frame)
        s, c = fmath.sincos(pose.yaw)
        staging = Pose2D(
            pose.x + c * p.staging_x_offset,
            pose.y + s * p.staging_x_offset,
            pose.yaw + p.staging_yaw_offset,
        )
        self.staging_pose = PoseStamped(self.context.now, staging, frame)
        return self.staging_pose

    def on_detected_dock_pose(self, msg: PoseStamped3D) -> None:
        if self.subscribed:
            self.detected = msg
            self.initial_pose_received = True

    def get_refined_pose(self, pose: PoseStamped, dock_id: str = "") -> PoseStamped | None:
        p = self.params
        if not p.use_external_detection_pose:
            self.dock_pose = pose
            return pose
        detected = self.detected
        if not self.initial_pose_received or detected is None:
            return None
        if self.context.now - detected.stamp > p.external_detection_timeout:
            return None  # lost the detection, or never had one recently
        if detected.frame_id != pose.frame_id:
            try:
                tf = self.context.lookup(pose.frame_id, detected.frame_id)
                detected = in_frame(detected, pose.frame_id, tf)
            except FrameError:
                return None
        detected = self.filter.update(detected)
        yaw = yaw_of(multiply(detected.orientation, self.rotation))
        s, c = fmath.sincos(yaw)
        tx, ty = p.external_detection_translation_x, p.external_detection_translation_y
        x, y, _ = detected.position
        refined = Pose2D(x + c * tx - s * ty, y + s * tx + c * ty, yaw)
        self.dock_pose = PoseStamped(detected.stamp, refined, detected.frame_id)
        return self.dock_pose

    def start_detection_process(self) -> bool:
        if not self.detection_active:
            if self.params.subscribe_toggle:
                self.subscribed = True
            self.detection_active = True
        return True

    def stop_detection_process(self) -> bool:
        if self.detection_active:
            if self.params.subscribe_toggle:
                self.subscribed = False
            self.detection_active = False
            self.initial_pose_received = False
        return True

    # -- state ------------------------------------------------------------------------

    def is_docked(self) -> bool:
        if not self.dock_pose.frame_id:
            return False
        try:
            base = self.context.lookup(self.dock_pose.frame_id, self.context.base_frame)
        except FrameError:
            return False
        dock = self.dock_pose.pose
        return bool(fmath.hypot(base.x - dock.x, base.y - dock.y) < self.params.docking_threshold)

    @property
    def dock_direction(self) -> DockDirection:
        return DockDirection(self.params.dock_direction)

    def should_rotate_to_dock(self) -> bool:
        return self.params.rotate_to_dock


def in_frame(pose: PoseStamped3D, frame: str, tf: Pose2D) -> PoseStamped3D:
    """A 3D pose taken into another frame of the ground plane (`tf`: frame <- pose's frame)."""
    x, y, z = pose.position
    s, c = fmath.sincos(tf.yaw)
    position = (tf.x + c * x - s * y, tf.y + s * x + c * y, z)
    return PoseStamped3D(pose.stamp, frame, position, multiply(from_yaw(tf.yaw), pose.orientation))
