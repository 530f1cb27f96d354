"""Recovery behaviours as nav2_behaviors does them: Spin, BackUp, DriveOnHeading, Wait.

Each is a `behavior` plugin (`nav2_behaviors::Spin`, ...) run by the behavior_server
(`btnav.nav.behavior_server`) at `cycle_frequency`, one action server per name.
"""

from .back_up import BackUp, BackUpFeedback, BackUpGoal
from .behavior import Behavior, BehaviorEnv, BehaviorOutcome, BehaviorResult
from .collision import CollisionChecker
from .drive_on_heading import DriveOnHeading, DriveOnHeadingFeedback, DriveOnHeadingGoal
from .spin import Spin, SpinFeedback, SpinGoal
from .wait import Wait, WaitFeedback, WaitGoal

__all__ = [
    "BackUp",
    "BackUpFeedback",
    "BackUpGoal",
    "Behavior",
    "BehaviorEnv",
    "BehaviorOutcome",
    "BehaviorResult",
    "CollisionChecker",
    "DriveOnHeading",
    "DriveOnHeadingFeedback",
    "DriveOnHeadingGoal",
    "Spin",
    "SpinFeedback",
    "SpinGoal",
    "Wait",
    "WaitFeedback",
    "WaitGoal",
]
