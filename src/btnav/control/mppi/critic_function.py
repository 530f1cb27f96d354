"""The base of MPPI's critics (mppi::critics::CriticFunction): score a whole batch at once.

A critic adds its cost to `data.costs` (one float32 per trajectory) with whole-array
operations over the batch; it never loops over trajectories. Critics are plugins of
kind `critic`, registered as `mppi::critics::<Name>`; the controller's `critics:`
list names them without the namespace, as Nav2's does.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from pydantic import Field

from ...params.schema import ParamsModel
from .critic_data import CriticData

#: The namespace Nav2 adds to the names in the `critics:` list.
NAMESPACE = "mppi::critics::"


class CriticFunction:
    """One term of MPPI's objective: `score` adds `(weight * term) ** power` to `data.costs`."""

    class Params(ParamsModel):
        enabled: bool = True
        cost_weight: float = Field(1.0, ge=0.0)
        cost_power: int = Field(1, ge=1)

    plugin_kind: ClassVar[str]
    plugin_name: ClassVar[str]

    def __init__(self, name: str, params: Params | None = None) -> None:
        self.name = name
        self.params = params if params is not None else self.Params()
        self.weight = np.float32(self.params.cost_weight)
        self.power = int(self.params.cost_power)

    #: The local costmap server (Nav2's costmap_ros_), once the controller is configured.
    costmap_ros: Any = None

    def configure(self, costmap_ros: Any) -> None:
        """Nav2's on_configure: the costmap server whose footprint and layers critics read."""
        self.costmap_ros = costmap_ros

    @property
    def enabled(self) -> bool:
        return bool(self.params.enabled)

    def score(self, data: CriticData) -> None:
        raise NotImplementedError

    def add(self, data: CriticData, term: np.ndarray) -> None:
        """`data.costs += (weight * term) ** power` (term: one value per trajectory)."""
        term = term * self.weight
        if self.power != 1:
            term = term**self.power
        data.costs += term.astype(np.float32, copy=False)
