"""The sensor plugin base: a device mounted on the robot that measures the world at a rate."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from pydantic import Field

from ..core.geometry import Pose2D
from ..core.validation import StrictModel
from ..plugins import Plugin

if TYPE_CHECKING:
    from .world import World


class Sensor(Plugin):
    """Base of every sensor plugin (`@register("sensor", name)`).

    A world file lists sensors as one-key mappings (`- lidar: {...}`); the key is
    the plugin name and the value is validated by the plugin's `Params`. Built as every
    plugin is, `cls(name, params)`; then `configure(world, rng)` hands it the world it
    measures and its own seeded noise stream.
    """

    class Params(StrictModel):
        frame: str = Field(description="the sensor's frame id, a child of base_link")
        pose: tuple[float, float, float] = Field(
            (0.0, 0.0, 0.0), description="mounting pose [x, y, yaw] in base_link"
        )
        rate: float = Field(
            10.0, gt=0, le=10_000, description="measurements per second of sim time"
        )

    params: Params
    world: World
    rng: np.random.Generator

    def __init__(self, name: str, params: Params) -> None:
        super().__init__(name, params)
        self.frame_id = params.frame
        self.mount = Pose2D(*params.pose)
        self.rate = params.rate

    def configure(self, world: World, rng: np.random.Generator) -> None:  # type: ignore[override]
        self.world = world
        self.rng = rng

    def measure(self, now: float) -> Any:
        """Take one measurement of the world as it is now, stamped `now`."""
        raise NotImplementedError
