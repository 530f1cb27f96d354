"""Importing this module registers btnav's built-in costmap plugins (entry point `btnav.plugins`)."""
