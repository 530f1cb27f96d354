"""Recovery behaviours as nav2_behaviors does them: Spin, BackUp, DriveOnHeading, Wait.

Each is a `behavior` plugin (`nav2_behaviors::Spin`, ...) run by the behavior_server
(`btnav.nav.behavior_server`) at `cycle_frequency`, one action server per name. Their
goals and feedback are in `btnav.core.nav2_msgs`.
"""

from .back_up import BackUp
from .behavior import Behavior, BehaviorEnv, BehaviorOutcome
from .collision import CollisionChecker
from .drive_on_heading import DriveOnHeading
from .spin import Spin
from .wait import Wait

__all__ = [
    "BackUp",
    "Behavior",
    "BehaviorEnv",
    "BehaviorOutcome",
    "CollisionChecker",
    "DriveOnHeading",
    "Spin",
    "Wait",
]
