"""The `viz` entry point: importing this registers every output plugin of this package."""

from . import run_plot  # noqa: F401  (`png`)
from .foxglove_live import FoxgloveOutput  # noqa: F401  (`foxglove`: foxglove-sdk imported on use)
from .live.recording import Recording  # noqa: F401  (`recording`)
from .rosbag_output import RosbagOutput  # noqa: F401  (`bag`)
from .run_gif import RunGif  # noqa: F401  (`gif`)
