"""What the example's tests share: its own files, btnav's office map, a clean blackboard.

The tests import `btnav_example` as installed (`pip install ./plugins/btnav_example`);
importing it registers the four plugins, as btnav's entry-point discovery would.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import py_trees
import pytest
from btnav.core.geometry import Pose2D
from btnav.core.resources import bundled_dir
from btnav.costmap import CostmapROS
from btnav.maps import load_map
from btnav.params import load_params

import btnav_example  # noqa: F401  (registers the plugins)

#: The example package's folder (params/, trees/, missions/ beside src/ and tests/).
PACKAGE = Path(__file__).resolve().parents[1]
EXAMPLE_PARAMS = PACKAGE / "params" / "example_params.yaml"
OFFICE_MAP = bundled_dir("maps") / "small_office.yaml"
OFFICE_WORLD = bundled_dir("worlds") / "small_office.yaml"


@pytest.fixture(scope="session")
def example_params():
    return load_params(EXAMPLE_PARAMS)


@pytest.fixture
def office_costmap(example_params) -> CostmapROS:
    """The example's global costmap (static map, keepout zones, inflation) on the office."""
    costmap = CostmapROS.from_params(example_params, "global_costmap", map=load_map(OFFICE_MAP))
    costmap.update(Pose2D(1.0, 1.0, 0.0), force=True)
    return costmap


@pytest.fixture(autouse=True)
def clean_blackboard() -> Iterator[None]:
    """py_trees' blackboard is process-wide: every test starts with an empty one."""
    py_trees.blackboard.Blackboard.clear()
    yield
    py_trees.blackboard.Blackboard.clear()
