"""Savitzky-Golay smoothing of the optimal control sequence, with the applied-control history."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: A 9-point quadratic Savitzky-Golay smoothing window.
SG_WINDOW = np.array([-21, 14, 39, 54, 59, 54, 39, 14, -21], dtype=np.float32) / np.float32(231.0)
HISTORY = 4  # half the window: the last controls actually sent


def savitzky_golay(sequence: NDArray[np.float32], history: NDArray[np.float32]) -> None:
    """Smooth `sequence` (T, C) in place; its past is `history` (4, C), its future the last value held."""
    t = sequence.shape[0]
    padded = np.concatenate([history, sequence, np.repeat(sequence[-1:], HISTORY, axis=0)], axis=0)
    # The window's taps added in order (np.convolve sums with BLAS: CPU-dependent bits);
    # the window is symmetric, so this is the convolution.
    out = padded[:t] * SG_WINDOW[0]
    for j in range(1, len(SG_WINDOW)):
        out += padded[j : j + t] * SG_WINDOW[j]
    sequence[...] = out
