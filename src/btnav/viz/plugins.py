"""The `viz` entry point: importing this registers every output plugin of this package."""

from . import run_plot  # noqa: F401  (`png`)
