"""Localisers: they publish map -> odom (ground truth now; AMCL to come)."""
