"""Which path MPPI's hot loops take: the numba kernels or the numpy reference.

Both give the same bits (tests compare them); `BTNAV_MPPI=numpy` in the environment
runs the reference, to check a kernel or to run where numba cannot compile.
"""

from __future__ import annotations

import os
from typing import Literal

KernelMethod = Literal["kernel", "numpy"]

#: "kernel" unless the environment says BTNAV_MPPI=numpy.
DEFAULT_METHOD: KernelMethod = "numpy" if os.environ.get("BTNAV_MPPI") == "numpy" else "kernel"
