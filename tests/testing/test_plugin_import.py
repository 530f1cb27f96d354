"""The plugin loads in every pytest session, so loading it must cost next to nothing."""

from __future__ import annotations

import subprocess
import sys

HEAVY = ("numpy", "pymunk", "scipy", "py_trees", "btnav.mission", "btnav.nav", "btnav.sim")


def test_importing_the_plugin_imports_no_part_of_the_stack():
    code = f"import sys, btnav.testing; print(sorted(m for m in {HEAVY!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_the_entry_point_loaded_the_plugin_here(pytestconfig):
    import btnav.testing

    assert pytestconfig.pluginmanager.get_plugin("btnav") is btnav.testing
    assert pytestconfig.getoption("btnav_out") is None  # option known, not given
