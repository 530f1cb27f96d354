"""Localisers: they publish map -> odom (`ground_truth` for tests, `amcl` on a known map)."""
