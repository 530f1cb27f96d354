"""Simulated time. Nothing in btnav reads the wall clock to decide anything."""

from __future__ import annotations

NS_PER_S = 1_000_000_000


class SimClock:
    """Sim time kept in integer nanoseconds, so a million 0.01 s steps add up exactly."""

    __slots__ = ("_ns", "now")

    #: Seconds since the start of the run (`now_ns` / 1e9, worked out once per advance:
    #: every component reads it, and a slot is a specialised read, a property is not).
    now: float

    def __init__(self, start: float = 0.0) -> None:
        self._ns = round(start * NS_PER_S)
        self.now = self._ns / NS_PER_S

    @property
    def now_ns(self) -> int:
        return self._ns

    def advance(self, dt: float) -> float:
        """Move time forward by `dt` seconds (rounded to the nanosecond); returns the new time."""
        step = round(dt * NS_PER_S)
        if step < 0:
            raise ValueError("sim time never runs backwards")
        self._ns += step
        self.now = self._ns / NS_PER_S
        return self.now

    def __repr__(self) -> str:
        return f"SimClock(now={self.now:.9f})"


class Rate:
    """Says when a component running at `hz` is due, on sim time and without drift."""

    __slots__ = ("_next_ns", "period_ns")

    def __init__(self, hz: float, start: float = 0.0) -> None:
        if not hz > 0:
            raise ValueError(f"a rate must be positive, got {hz}")
        self.period_ns = round(NS_PER_S / hz)
        self._next_ns = round(start * NS_PER_S)

    def due(self, clock: SimClock) -> bool:
        """True (and schedules the next tick) when the clock has reached the next tick."""
        if clock.now_ns >= self._next_ns:
            # Skip ticks missed by a coarse caller instead of bursting to catch up.
            missed = (clock.now_ns - self._next_ns) // self.period_ns
            self._next_ns += (missed + 1) * self.period_ns
            return True
        return False

    @property
    def period(self) -> float:
        return self.period_ns / NS_PER_S
