"""Importing this module registers btnav's built-in control plugins (entry point `btnav.plugins`)."""
