"""Pace a run to wall time for a viewer: sim time runs at `speed` times the wall clock.

Pacing only sleeps between steps; it never changes what a step computes, so a paced
run gives the same trajectory bytes as an unpaced one. `speed` 0 runs as fast as the
machine goes. A change of speed (or a pause) re-anchors the clocks, so the run does
not race to catch up the time it was held.
"""

from __future__ import annotations

import time
from collections.abc import Callable


class Pacer:
    """Holds each step until the wall clock has caught up with sim time / speed."""

    def __init__(
        self,
        speed: float = 1.0,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        if speed < 0:
            raise ValueError(f"speed must be >= 0 (0: as fast as it goes), not {speed}")
        self._speed = speed
        self._clock = clock
        self._sleep = sleep
        self._anchor: tuple[float, float] | None = None  # (sim time, wall time)

    @property
    def speed(self) -> float:
        return self._speed

    @speed.setter
    def speed(self, speed: float) -> None:
        if speed < 0:
            raise ValueError(f"speed must be >= 0 (0: as fast as it goes), not {speed}")
        self._speed = speed
        self.reanchor()

    def reanchor(self) -> None:
        """Forget the past: the next `wait` starts a new stretch (after a pause or step)."""
        self._anchor = None

    def wait(self, sim_now: float) -> None:
        """Sleep until wall time has caught up with `sim_now` at the current speed."""
        if self._speed == 0:
            return
        wall = self._clock()
        if self._anchor is None:
            self._anchor = (sim_now, wall)
            return
        sim0, wall0 = self._anchor
        ahead = (sim_now - sim0) / self._speed - (wall - wall0)
        if ahead > 0:
            self._sleep(ahead)
        elif ahead < -0.25:  # the machine fell behind: do not race to catch up later
            self._anchor = (sim_now, wall)
