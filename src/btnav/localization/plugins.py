"""Importing this module registers btnav's built-in localisers (entry point `btnav.plugins`)."""

from . import (
    amcl,  # noqa: F401
    ground_truth,  # noqa: F401
)
