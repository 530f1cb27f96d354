from __future__ import annotations

import numpy as np
import pytest

from btnav.core.clock import Rate, SimClock
from btnav.core.rng import stream


def test_a_million_steps_add_up_exactly():
    clock = SimClock()
    for _ in range(100_000):
        clock.advance(0.01)
    assert clock.now == 1000.0


def test_rate_ticks_at_its_period_on_sim_time():
    clock, rate = SimClock(), Rate(10.0)
    ticks = []
    for _ in range(1000):  # 10 s at 100 Hz
        if rate.due(clock):
            ticks.append(clock.now)
        clock.advance(0.01)
    assert len(ticks) == 100
    assert np.allclose(np.diff(ticks), 0.1)


def test_clock_never_runs_backwards():
    with pytest.raises(ValueError):
        SimClock().advance(-1.0)


def test_streams_depend_only_on_seed_and_name():
    a = stream(3, "odometry").normal(size=5)
    assert np.array_equal(a, stream(3, "odometry").normal(size=5))
    assert not np.array_equal(a, stream(4, "odometry").normal(size=5))
    assert not np.array_equal(a, stream(3, "lidar").normal(size=5))
