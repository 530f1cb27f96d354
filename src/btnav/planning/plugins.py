"""Importing this module registers btnav's built-in planning plugins (entry point `btnav.plugins`)."""
