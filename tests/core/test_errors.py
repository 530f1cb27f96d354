"""A user's mistake and a user's likely mistake read the same way: file:line: key: message."""

from __future__ import annotations

import warnings

import pytest

from btnav.core.errors import BtnavError, BtnavWarning


def test_an_error_and_a_warning_name_their_place_alike():
    err = BtnavError(
        "unknown key 'x'", file="w.yaml", line=3, key=["robot", "limits"], suggestion="y"
    )
    assert str(err) == "w.yaml:3: robot.limits: unknown key 'x' (did you mean 'y'?)"
    warning = BtnavWarning("odd", file="w.yaml", line=3, key=["obstacles", 2, "circle"])
    assert str(warning) == "w.yaml:3: obstacles[2].circle: odd"
    assert str(BtnavWarning("odd", file="--set a.b=1")) == "--set a.b=1: odd"


def test_a_warning_is_a_python_warning_tests_can_catch():
    with pytest.warns(BtnavWarning, match=r"^w\.yaml:3: odd$"):
        warnings.warn(BtnavWarning("odd", file="w.yaml", line=3), stacklevel=1)
