"""The sensor plugin base: a device mounted on the robot that measures the world at a rate."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from pydantic import Field

from ..core.geometry import Pose2D
from ..core.validation import StrictModel

if TYPE_CHECKING:
    from .world import World


class Sensor:
    """Base of every sensor plugin (`@register("sensor", name)`).

    A world file lists sensors as one-key mappings (`- lidar: {...}`); the key is
    the plugin name and the value is validated by the plugin's `Params`.
    """

    class Params(StrictModel):
        frame: str = Field(description="the sensor's frame id, a child of base_link")
        pose: tuple[float, float, float] = Field(
            (0.0, 0.0, 0.0), description="mounting pose [x, y, yaw] in base_link"
        )
        rate: float = Field(
            10.0, gt=0, le=10_000, description="measurements per second of sim time"
        )

    plugin_kind: ClassVar[str]
    plugin_name: ClassVar[str]

    def __init__(self, params: Params, world: World, rng: np.random.Generator) -> None:
        self.params = params
        self.world = world
        self.rng = rng
        self.frame_id = params.frame
        self.mount = Pose2D(*params.pose)
        self.rate = params.rate

    def measure(self, now: float) -> Any:
        """Take one measurement of the world as it is now, stamped `now`."""
        raise NotImplementedError
