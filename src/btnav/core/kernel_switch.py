"""Which path a compiled hot loop takes: its numba kernel or the numpy reference.

Both give the same bits (each kernel's tests compare them); an area's environment
variable set to `numpy` (BTNAV_COSTMAP, BTNAV_NAVFN, BTNAV_RAYCAST) runs the reference,
to check a kernel or to run where numba cannot compile.
"""

from __future__ import annotations

import os
from typing import Literal

Method = Literal["kernel", "numpy"]


def default_method(variable: str) -> Method:
    """ "numpy" when the environment sets `variable` to numpy, else "kernel"."""
    return "numpy" if os.environ.get(variable) == "numpy" else "kernel"
