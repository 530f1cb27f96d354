"""Importing this module registers btnav's built-in localisers (entry point `btnav.plugins`)."""

from . import ground_truth  # noqa: F401
