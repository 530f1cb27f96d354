"""Savitzky-Golay smoothing of the optimal control sequence, with the applied-control history."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: The 9-point smoothing windows: quadratic (sgf_order 2) and linear, a moving average (1).
SG_WINDOWS = {
    2: np.array([-21, 14, 39, 54, 59, 54, 39, 14, -21], dtype=np.float32) / np.float32(231.0),
    1: np.full(9, 1.0, dtype=np.float32) / np.float32(9.0),
}
HISTORY = 4  # half the window: the last controls actually sent
#: Shorter sequences are not smoothed (Nav2: too short to smooth meaningfully).
MIN_STEPS = 21


def savitzky_golay(
    sequence: NDArray[np.float32], history: NDArray[np.float32], order: int = 2, sent: int = 0
) -> None:
    """Smooth `sequence` (T, C) in place but its last step (Nav2 leaves it), its past
    `history` (4, C), its future the last value held; then push step `sent` (the one
    the robot will be sent) onto the history."""
    t = sequence.shape[0] - 1
    if t + 1 < MIN_STEPS:
        return
    window = SG_WINDOWS[order]
    padded = np.concatenate([history, sequence, np.repeat(sequence[-1:], HISTORY - 1, axis=0)])
    # The window's taps added in order (np.convolve sums with BLAS: CPU-dependent bits);
    # the window is symmetric, so this is the convolution.
    out = padded[:t] * window[0]
    for j in range(1, len(window)):
        out += padded[j : j + t] * window[j]
    sequence[:t] = out
    history[:-1] = history[1:]
    history[-1] = sequence[sent]
