"""Seeded random streams: every random number in a run comes from the mission seed.

Each consumer (odometry noise, lidar noise, AMCL, MPPI, ...) asks for its own
stream by name, so adding a consumer does not shift the numbers any other one draws.
"""

from __future__ import annotations

import zlib

import numpy as np


def stream(seed: int, *names: str) -> np.random.Generator:
    """A generator determined only by the seed and the names (stable across runs and machines)."""
    if seed < 0:
        raise ValueError(f"a seed is a non-negative integer, got {seed}")
    key = [zlib.crc32(name.encode("utf-8")) for name in names]
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed, spawn_key=key)))
