"""Sampling noise for MPPI's rollouts (mppi::NoiseGenerator), fast and seeded.

Drawing 2 x 2000 x 56 float32 normals costs ~2 ms in numpy, a fifth of the cycle
budget, so noise comes from a pool: `pool_factor` batches of independent N(0, 1)
columns per control channel, generated from the controller's
`numpy.random.Generator`. Each cycle takes, per channel, `batch_size` consecutive
columns from a random offset in the pool (no gather: a strided view), flips the
sign of each rollout at random and scales by vx_std / wz_std (/ vy_std). With
`regenerate_noises` (Nav2: "sample a new distribution each cycle") a slice
(`refresh_fraction` of the pool) is also redrawn every cycle, so the pool turns over
continuously; without it the pool stays fixed, as Nav2 reuses one noise set until a
reset. Either way the noise is a pure function of the seed.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .perturb_kernel import perturb


class NoiseGenerator:
    def __init__(
        self,
        rng: np.random.Generator,
        batch_size: int,
        time_steps: int,
        stds: tuple[float, ...],
        regenerate: bool,
        pool_factor: int = 4,
        refresh_fraction: float = 1.0 / 32.0,
    ) -> None:
        """`stds`: one standard deviation per control channel, in the optimizer's channel order."""
        self.rng = rng
        self.batch_size = batch_size
        self.time_steps = time_steps
        self.stds = np.asarray(stds, dtype=np.float32)
        self.channels = len(stds)
        self.regenerate = regenerate
        self.pool_cols = max(pool_factor, 1) * batch_size
        self.refresh_cols = max(1, int(self.pool_cols * refresh_fraction))
        self._cursor = 0
        self.reset()

    def reset(self) -> None:
        """Draw a fresh pool (Nav2 regenerates noise on reset)."""
        self.pool = self.rng.standard_normal(
            (self.channels, self.time_steps, self.pool_cols), dtype=np.float32
        )
        self._cursor = 0

    def _draw(self) -> tuple[NDArray[np.int64], NDArray[np.float32]]:
        """This iteration's random choices: the pool's refreshed slice (with
        `regenerate`), each channel's offset into the pool, and the (C, B) scale rows
        (a random sign per rollout times the channel's std)."""
        if self.regenerate:
            lo = self._cursor
            hi = min(lo + self.refresh_cols, self.pool_cols)
            self.pool[:, :, lo:hi] = self.rng.standard_normal(
                (self.channels, self.time_steps, hi - lo), dtype=np.float32
            )
            self._cursor = 0 if hi >= self.pool_cols else hi
        b = self.batch_size
        starts = self.rng.integers(0, self.pool_cols - b + 1, self.channels)
        signs = np.where(self.rng.random(b) < 0.5, np.float32(-1.0), np.float32(1.0))
        scale = np.empty((self.channels, b), np.float32)
        for ch in range(self.channels):
            np.multiply(signs, self.stds[ch], out=scale[ch])
        return starts, scale

    def sample(self, out: NDArray[np.float32]) -> NDArray[np.float32]:
        """Noise for one iteration, (time_steps, channels, batch_size), written into `out`
        (the optimizer's controls buffer: no buffer of its own)."""
        starts, scale = self._draw()
        b = self.batch_size
        for ch in range(self.channels):
            np.multiply(self.pool[ch, :, starts[ch] : starts[ch] + b], scale[ch], out=out[:, ch, :])
        return out

    def sample_controls(self, out: NDArray[np.float32], sequence: NDArray[np.float32]) -> None:
        """`sample(out)` plus the (T, C) control `sequence`, in one compiled pass
        (perturb_kernel.py, the same bits as the multiply and the add)."""
        starts, scale = self._draw()
        perturb(self.pool, starts, scale, sequence, out)
