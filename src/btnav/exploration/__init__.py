"""Exploration: frontiers on the live map, and which one to visit next (explore_lite's role)."""
