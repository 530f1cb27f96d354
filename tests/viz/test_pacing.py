"""A paced run holds sim time to the wall clock times the speed."""

import pytest

from btnav.viz.pacing import Pacer


class FakeClock:
    def __init__(self) -> None:
        self.now = 0.0
        self.slept: list[float] = []

    def __call__(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.slept.append(seconds)
        self.now += seconds


def test_sim_time_runs_at_speed_times_wall_time() -> None:
    clock = FakeClock()
    pacer = Pacer(10.0, clock, clock.sleep)
    for step in range(101):  # 100 steps of 0.05 s sim = 5 s sim
        pacer.wait(step * 0.05)
    assert clock.now == pytest.approx(0.5)


def test_speed_zero_never_sleeps() -> None:
    clock = FakeClock()
    pacer = Pacer(0.0, clock, clock.sleep)
    for step in range(100):
        pacer.wait(step * 0.05)
    assert clock.slept == []


def test_a_pause_is_not_caught_up_afterwards() -> None:
    clock = FakeClock()
    pacer = Pacer(1.0, clock, clock.sleep)
    pacer.wait(0.0)
    pacer.wait(1.0)
    clock.now += 30.0  # held by a pause
    pacer.reanchor()
    pacer.wait(1.05)
    pacer.wait(2.05)
    assert clock.now == pytest.approx(32.0)


def test_negative_speed_is_refused() -> None:
    with pytest.raises(ValueError, match="speed must be >= 0"):
        Pacer(-1.0)
