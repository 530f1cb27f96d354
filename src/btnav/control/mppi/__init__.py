"""Nav2's MPPI controller (nav2_mppi_controller) in numpy: optimizer, noise, motion models, critics.

Importing the package registers the controller (`nav2_mppi_controller::MPPIController`)
and its critics (kind `critic`, `mppi::critics::<Name>`).
"""

from . import critics  # noqa: F401  (registers the critics before the params need them)
from .controller import MPPIController
from .critic_data import CriticData
from .critic_function import CriticFunction
from .params import MPPIParams

__all__ = ["CriticData", "CriticFunction", "MPPIController", "MPPIParams"]
