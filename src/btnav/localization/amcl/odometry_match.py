"""AMCL's alphas against a world's wheel odometry: the conversion, and the note when they differ.

A btnav world gives its odometry noise as variances *per metre and per radian* of
motion (`sim/odometry_noise.py`: var(rot1) = a1 |rot1| + a2 |trans| per odometry step,
so the drift of a path does not depend on the odometry rate). nav2_amcl's motion models
take alpha times the *square* of one filter update's motion as the variance
(var(rot1) = alpha1 rot1^2 + alpha2 trans^2, and so on). The same numbers in the two
places mean different things: alphas set to a world's noise give AMCL a quarter of the
world's drift over a 0.25 m update (a cloud that cannot follow the robot, which is how
issue 34's warehouse diverged within 5 m), and Nav2's 0.2 against btnav's bundled
odometry ([0.002, 0.0005, 0.0001, 0.0001]) is 20-500 times the drift (a cloud ~15 degrees
wide whose mean trails the robot along an aisle).

The two agree for an update of exactly the gates, update_min_d of driving or
update_min_a of turning:

    alpha1 = a1 / update_min_a   alpha2 = a2 / update_min_d
    alpha3 = a3 / update_min_d   alpha4 = a4 / update_min_a   (alpha5 = a5 / update_min_d)

(`world_noise_alphas`). AMCL needs more than that, for two reasons: its variance falls
with the square of a shorter motion, and the secondary motion of an update (the turn
inside a driving update, the drive inside a turning one) is often a tenth of its gate;
and the wheels drift with every wiggle of the heading (the sum of |turn| over the
odometry steps) where AMCL sees only the update's net turn. `matched_alphas` takes
MARGIN (10) times the conversion. Measured on the office tour (MPPI, AMCL driving,
seeds 0-2): 4x the conversion 3.7-4.7 cm RMS, 10x 2.1-3.6 cm, Nav2's 0.2 (20-500x)
4.6-5.4 cm; beside ground-truth driving (seed 0): 1x 4.0 cm, 3x 3.6, 10x 2.8, 30x 3.6.

`alpha_mismatch_note` is the one line `btnav run` prints when a mission's amcl alphas
are more than NOTE_RATIO times the conversion (the matched alphas sit at it) or more
than UNDER_RATIO times below it: too little noise is what loses a robot (issue 34's
warehouse with its alphas set to the world's numbers), so it is flagged sooner. Worlds
whose odometry comes from the laser, or is exact, get none.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

#: The matched alphas' factor over the exact conversion at the gates (see the module).
MARGIN = 10.0
#: Alphas more than this many times the world's noise in AMCL's units earn the note.
NOTE_RATIO = 10.0
#: ... and this many times below it (AMCL trusting the odometry more than it deserves).
UNDER_RATIO = 2.0

#: Which gate each alpha's motion is measured in: d (metres) or a (radians).
_GATE = ("a", "d", "d", "a", "d")


def world_noise_alphas(
    noise: Sequence[float], update_min_d: float, update_min_a: float
) -> tuple[float, ...]:
    """A world's odometry noise (variance per metre / radian) in AMCL's units: the alphas
    whose variance over one update of the gates equals the world's."""
    gates = {"d": max(float(update_min_d), 1e-3), "a": max(float(update_min_a), 1e-3)}
    return tuple(float(n) / gates[g] for n, g in zip(noise, _GATE, strict=False))


def matched_alphas(
    noise: Sequence[float], update_min_d: float, update_min_a: float, margin: float = MARGIN
) -> tuple[float, ...]:
    """The alphas btnav recommends for a world's odometry: `margin` x the conversion."""
    return tuple(margin * a for a in world_noise_alphas(noise, update_min_d, update_min_a))


def _fmt(values: Sequence[float]) -> str:
    return "[" + ", ".join(f"{v:.3g}" for v in values) + "]"


def _times(ratio: float) -> str:
    return f"{ratio:.0f}" if ratio >= 10.0 else f"{ratio:.2g}"


def alpha_mismatch_note(
    noise: Sequence[float],
    alphas: Sequence[float],
    update_min_d: float,
    update_min_a: float,
    *,
    source: str = "wheels",
) -> str | None:
    """The note (its message; the caller places it at the amcl section) for a mission whose
    amcl `alphas` (alpha1.. as many as `noise` has: four for the differential model, five
    for omni) and world odometry `noise` differ by more than NOTE_RATIO (over) or
    UNDER_RATIO (under); None when they agree, when the odometry is the laser's, or when
    the world's odometry is exact."""
    if source != "wheels":
        return None
    n = len(noise)
    ref = world_noise_alphas(noise, update_min_d, update_min_a)
    given = [float(a) for a in alphas[:n]]
    ratios = [g / r for g, r in zip(given, ref, strict=True) if r > 0.0]
    if not ratios:
        return None
    hi, lo = max(ratios), min(ratios)
    if round(hi, 9) <= NOTE_RATIO and round(lo, 9) >= 1.0 / UNDER_RATIO:
        return None
    names = f"alpha1-{n}"
    if hi > NOTE_RATIO:
        spread = f"{_times(lo)}-{_times(hi)}x" if lo < 0.95 * hi else f"{_times(hi)}x"
    else:
        spread = f"as little as {_times(lo)}x"
    matched = matched_alphas(noise, update_min_d, update_min_a)
    return (
        f"{names} {_fmt(given)} are {spread} the world's odometry noise {_fmt(noise)} in "
        f"AMCL's units (alphas scale the square of an update's motion, the world's noise is "
        f"per metre and radian); {names} {_fmt(matched)} match it "
        f"(btnav.localization.amcl.odometry_match)"
    )


def odometry_note(odometry: Any, amcl: Any) -> str | None:
    """`alpha_mismatch_note` for a world's `OdometrySpec` and validated amcl params."""
    alphas = (amcl.alpha1, amcl.alpha2, amcl.alpha3, amcl.alpha4, amcl.alpha5)
    return alpha_mismatch_note(
        odometry.noise, alphas, amcl.update_min_d, amcl.update_min_a, source=odometry.source
    )
