"""plugins/btnav_example, the example plugin package: from its files, and installed in a fresh venv.

The fast tests load the example's modules the way a mission's `plugins:` list does
(`.py` files, nothing installed): a planner in a single file runs a whole mission.
The slow test installs the package into a new virtual environment, as a user would,
and runs its mission (found through the `btnav.plugins` entry points alone) and its
own tests there.
"""

from __future__ import annotations

import json
import os
import shutil
import site
import subprocess
import sys
import sysconfig
import textwrap
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from btnav import plugins
from btnav.core.geometry import Pose2D
from btnav.costmap import CostmapROS
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from btnav.maps import load_map
from btnav.mission import Mission, run_mission
from btnav.params import load_params

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "plugins" / "btnav_example"
MODULES = EXAMPLE / "src" / "btnav_example"
MODULE_FILES = [
    MODULES / f"{name}.py"
    for name in ("astar_planner", "pure_pursuit", "keepout_zones_layer", "is_path_longer_than")
]
OFFICE_MAP = REPO / "maps" / "small_office.yaml"


def _forget(modules: list[ModuleType]) -> None:
    """Unregister what the modules registered and drop them, so other tests see btnav alone."""
    for module in modules:
        for value in vars(module).values():
            if getattr(value, "__module__", None) == module.__name__ and hasattr(
                value, "plugin_kind"
            ):
                plugins.unregister(value.plugin_kind, value.plugin_name)
        sys.modules.pop(module.__name__, None)


def _loaded_from(folder: Path) -> list[ModuleType]:
    return [
        m
        for m in list(sys.modules.values())
        if Path(getattr(m, "__file__", None) or "/").parent == folder
    ]


@pytest.fixture
def example_modules() -> Iterator[list[ModuleType]]:
    """The example's four modules, loaded from their files as a mission's `plugins:` does."""
    modules = plugins.load_plugins([str(p) for p in MODULE_FILES])
    yield modules
    _forget(modules)


def test_the_example_modules_load_from_their_files(example_modules):
    loaded = {module.__name__ for module in example_modules}
    for kind, name in (
        ("planner", "btnav_example::AStarPlanner"),
        ("controller", "btnav_example/PurePursuitController"),
        ("costmap_layer", "btnav_example::KeepoutZonesLayer"),
        ("bt_node", "IsPathLongerThan"),
    ):
        assert plugins.lookup(kind, name).__module__ in loaded


def test_its_planner_plans_round_its_layers_keepout_zone(example_modules):
    params = load_params(EXAMPLE / "params" / "example_params.yaml")
    costmap = CostmapROS.from_params(params, "global_costmap", map=load_map(OFFICE_MAP))
    costmap.update(Pose2D(1.0, 1.0, 0.0), force=True)
    grid = costmap.costmap
    assert grid.cost_at_point(7.05, 2.25) == LETHAL_OBSTACLE  # the keepout zone
    assert grid.cost_at_point(2.1, 1.9) == 150  # the slow zone
    planner = params.server("planner_server").plugin("GridBased")
    assert planner.cls.__name__ == "AStarPlanner"
    path = planner.cls("GridBased", planner.params).create_plan(
        Pose2D(1.0, 1.0, 0.0), Pose2D(9.0, 1.5, 0.0), grid
    )
    assert grid.cost_at(path.poses[:, :2]).max() < INSCRIBED_INFLATED_OBSTACLE
    assert path.poses[-1].tolist() == pytest.approx([9.0, 1.5, 0.0])


def test_a_planner_in_a_single_file_runs_a_mission(tmp_path):
    """A user's planner file named in `plugins:`, picked by the params' GridBased section."""
    (tmp_path / "my_planner.py").write_text((MODULES / "astar_planner.py").read_text())
    nav2 = (REPO / "params" / "nav2_params_rpp.yaml").read_text()
    navfn = textwrap.dedent(
        """\
            GridBased:
              plugin: "nav2_navfn_planner::NavfnPlanner"
              tolerance: 0.5
              use_astar: false
              max_cycles_factor: 4
              allow_unknown: true
        """
    )
    astar = '    GridBased:\n      plugin: "btnav_example::AStarPlanner"\n      cost_weight: 2.0\n'
    assert textwrap.indent(navfn, "    ") in nav2
    (tmp_path / "params.yaml").write_text(nav2.replace(textwrap.indent(navfn, "    "), astar))
    (tmp_path / "mission.yaml").write_text(
        textwrap.dedent(
            f"""\
            mission: single_file_planner
            world: {REPO / "worlds" / "small_office.yaml"}
            params: params.yaml
            map: {OFFICE_MAP}
            localization: ground_truth
            initial_pose: [1.0, 1.0, 0.0]
            task:
              navigate_to_pose: [3.0, 6.5, 1.57]
            time_limit: 60
            plugins: [my_planner.py]
            """
        )
    )
    try:
        mission = Mission.load(tmp_path / "mission.yaml")
        planner = mission.params.server("planner_server").plugin("GridBased").cls
        assert Path(sys.modules[planner.__module__].__file__) == tmp_path / "my_planner.py"
        report = run_mission(mission, None)
    finally:
        _forget(_loaded_from(tmp_path))
    assert report.status == "succeeded", report.error_msg
    assert report.collisions == 0


# -- installed, in a fresh virtual environment ---------------------------------------------


def _run(cmd: list[str], **kwargs) -> subprocess.CompletedProcess[str]:
    out = subprocess.run(cmd, capture_output=True, text=True, **kwargs)
    assert out.returncode == 0, f"{' '.join(map(str, cmd))}\n{out.stdout}\n{out.stderr}"
    return out


def _builds_offline() -> bool:
    """Whether setuptools can build a wheel here without pip's isolated build environment
    (it needs `wheel` before setuptools 70.1, which vendors it)."""
    try:
        import setuptools
    except ImportError:
        return False
    major, minor = (int(p) for p in setuptools.__version__.split(".")[:2])
    try:
        import wheel  # noqa: F401
    except ImportError:
        return (major, minor) >= (70, 1)
    return True


def _pip_install(python: Path, *args: str) -> None:
    """`pip install --no-deps` into the venv; without build isolation (no download) when the
    environment can build the wheel, else pip fetches setuptools from the package index."""
    isolation = ["--no-build-isolation"] if _builds_offline() else []
    _run([str(python), "-m", "pip", "install", "--no-deps", "-q", *isolation, *args])


def _fresh_venv(root: Path) -> Path:
    """A new venv that sees this environment's packages (btnav's dependencies, and btnav if
    installed), with the example package installed from a copy of its folder; its python."""
    venv = root / "venv"
    _run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)])
    python = venv / ("Scripts/python.exe" if os.name == "nt" else "bin/python")
    purelib = _run([str(python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"])
    # --system-site-packages shows the base interpreter's packages; when this run is itself
    # in a venv, its own site-packages are added so the new venv sees what this one has.
    here = [*site.getsitepackages(), sysconfig.get_path("purelib")]
    lines = [f"import site; site.addsitedir({d!r})" for d in dict.fromkeys(here)]
    Path(purelib.stdout.strip(), "_parent_env.pth").write_text("\n".join(lines) + "\n")
    has_btnav = subprocess.run([str(python), "-c", "import btnav"], capture_output=True)
    if has_btnav.returncode != 0:
        _pip_install(python, "-e", str(REPO))
    package = root / "btnav_example"  # built from a copy: no build files in the repo
    junk = shutil.ignore_patterns("__pycache__", "*.egg-info", "build", ".pytest_cache")
    shutil.copytree(EXAMPLE, package, ignore=junk)
    _pip_install(python, str(package))
    return python


@pytest.mark.slow
def test_installed_in_a_fresh_venv_its_mission_and_its_own_tests_pass(tmp_path):
    """`pip install ./plugins/btnav_example`, then a mission that names no `plugins:` finds
    the example's planner, controller, layer and BT node through the entry points alone."""
    python = _fresh_venv(tmp_path)
    where = _run([str(python), "-c", "import btnav_example; print(btnav_example.__file__)"])
    assert "site-packages" in where.stdout  # the installed copy, not the repo's folder
    mission = EXAMPLE / "missions" / "office_example.yaml"
    assert "\nplugins:" not in mission.read_text()
    out = tmp_path / "out"
    _run([str(python), "-m", "btnav.cli", "run", str(mission), "--out", str(out)])
    report = json.loads((out / "report.json").read_text())
    assert report["status"] == "succeeded"
    assert report["collisions"] == 0
    assert "IsPathLongerThan" in (out / "bt_log.jsonl").read_text()
    track = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1, usecols=(1, 2))
    assert np.hypot(track[-1, 0] - 9.0, track[-1, 1] - 1.5) < 0.3

    tests = _run(
        [str(python), "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:xdist"],
        cwd=tmp_path / "btnav_example",
    )
    assert " passed" in tests.stdout and "failed" not in tests.stdout
