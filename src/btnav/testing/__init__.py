"""btnav's pytest plugin (the `pytest11` entry point): fixtures, sim-time ticking, assertions.

Installed with btnav, it loads in every pytest session; it adds fixtures and the
`--btnav-out DIR` option and changes nothing for a test that uses neither.

```python
from btnav.testing import assert_no_collisions, assert_reached, run_mission, tick_until

def test_the_office_tour(btnav_tree):
    report = run_mission("office_tour", task={"navigate_to_pose": [3, 2, 1.57]})
    assert_reached(report)
    assert_no_collisions(report)
```

- fixtures: `btnav_mission`, `btnav_navigator`, `btnav_tree`, `btnav_world` (factories);
- `run_mission(path, **overrides) -> RunResult` (a `RunReport` that knows its folder),
  `load_mission`, `tick_until(tree_or_navigator, condition, timeout)`, `respond(...)`
  (a fake server's answer);
- `assert_reached`, `assert_no_collisions`, `assert_node_status`, `assert_within`.

Importing this module is cheap (no numpy, pymunk or the navigation stack): the
helpers load on first use.
"""

from __future__ import annotations

from ..core.lazy_names import lazy_names
from .fixtures import btnav_mission, btnav_navigator, btnav_tree, btnav_world
from .plugin import pytest_addoption, pytest_runtest_makereport, pytest_runtest_protocol

#: Helpers loaded on first use, by the module that holds them.
_LAZY = {
    "run_mission": "missions",
    "load_mission": "missions",
    "RunResult": "missions",
    "tick_until": "ticking",
    "TickResult": "ticking",
    "respond": "fake_servers",
    "FakeServer": "fake_servers",
    "TreeUnderTest": "tree",
    "RecordedNavigator": "navigator",
    "assert_reached": "assertions",
    "assert_no_collisions": "assertions",
    "assert_node_status": "assertions",
    "assert_within": "assertions",
}

__all__ = [
    "btnav_mission",
    "btnav_navigator",
    "btnav_tree",
    "btnav_world",
    "pytest_addoption",
    "pytest_runtest_makereport",
    "pytest_runtest_protocol",
    *_LAZY,
]


__getattr__ = lazy_names(__name__, _LAZY)
