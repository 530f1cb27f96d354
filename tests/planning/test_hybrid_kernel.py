"""SmacPlannerHybrid's compiled search makes the Python search's plans, bit for bit."""

from __future__ import annotations

import functools
import math
from pathlib import Path

import pytest

from btnav.core.geometry import Pose2D
from btnav.costmap.costmap_ros import CostmapROS
from btnav.maps import load_map
from btnav.params import load_params
from btnav.planning import hybrid_kernel
from btnav.planning.exceptions import PlannerException
from btnav.planning.smac_planner_hybrid import SmacPlannerHybrid

from .test_smac_planner_hybrid import corridor, office  # noqa: F401 (a fixture)

REPO = Path(__file__).resolve().parents[2]
#: bench/planner.py's racecar requests (start, goal) on the office.
RACECAR_REQUESTS = (
    ((1.0, 1.0, 0.0), (6.0, 3.0, math.pi)),
    ((1.0, 1.0, 0.0), (10.0, 6.0, math.pi / 2)),
    ((2.5, 1.0, 0.0), (1.0, 1.5, 0.0)),
    ((5.5, 2.5, 0.0), (9.5, 1.2, math.pi)),
    ((6.0, 2.0, 0.0), (6.0, 2.0, math.pi)),
)


def both(
    planner: SmacPlannerHybrid, start, goal, costmap, cancel_after: int | None = None
) -> tuple:
    """Each method's plan (its poses' bytes and expansions, or the exception's type), the
    search cancelled at the cancel checker's `cancel_after`th call if given."""
    out = []
    for method in ("kernel", "python"):
        planner.method = method
        cancel = None if cancel_after is None else _cancel_after(cancel_after)
        try:
            path = planner.create_plan(Pose2D(*start), Pose2D(*goal), costmap, cancel)
            out.append((path.poses.tobytes(), planner.expansions))
        except PlannerException as exc:
            out.append((type(exc).__name__, planner.expansions))
    return tuple(out)


def _cancel_after(n: int):
    """A cancel checker that says yes at its nth call."""
    calls = []

    def cancel() -> bool:
        calls.append(1)
        return len(calls) >= n

    return cancel


@pytest.fixture(scope="module")
def racecar() -> tuple[SmacPlannerHybrid, object]:
    params = load_params(REPO / "params" / "racecar_nav2_params.yaml")
    ros = CostmapROS.from_params(
        params, "global_costmap", map=load_map(REPO / "maps" / "small_office.yaml")
    )
    ros.refresh()
    hybrid = SmacPlannerHybrid(
        "GridBased", params.server("planner_server").plugins["GridBased"].params
    )
    hybrid.configure(ros)
    return hybrid, ros.costmap


@pytest.mark.parametrize(("start", "goal"), RACECAR_REQUESTS)
def test_the_racecars_plans_are_the_pythons(racecar, start, goal):
    hybrid, cm = racecar
    kernel, python = both(hybrid, start, goal, cm)
    assert kernel == python
    assert isinstance(kernel[0], bytes)


@pytest.mark.parametrize("model", ["DUBIN", "REEDS_SHEPP"])
@pytest.mark.parametrize(
    ("start", "goal", "extra"),
    [
        ((1, 1, 0), (6, 3, 3.14), {}),
        ((1, 1, 0), (10, 6, 1.57), {}),
        ((1, 1, 0), (6, 3, 3.14), {"allow_primitive_interpolation": True, "change_penalty": 0.3}),
        ((1, 1, 0), (10, 6, 1.57), {"max_iterations": 500}),  # times out
        ((1, 1, 0), (6, 3, 3.14), {"analytic_expansion_max_length": 0.05, "tolerance": 0.5}),
        (
            (1, 1, 0),
            (8, 4, 0.0),
            {"angle_quantization_bins": 16, "use_quadratic_cost_penalty": True},
        ),
    ],
)
def test_nav2s_defaults_on_the_office_plan_as_python_does(office, model, start, goal, extra):  # noqa: F811
    hybrid = SmacPlannerHybrid(
        "GridBased", SmacPlannerHybrid.Params(motion_model_for_search=model, **extra)
    )
    kernel, python = both(hybrid, start, goal, office)
    assert kernel == python


def test_no_path_a_cancel_and_little_room_end_as_python_does(monkeypatch):
    cm = corridor()
    hybrid = SmacPlannerHybrid("GridBased", SmacPlannerHybrid.Params(max_iterations=20000))
    start, goal = (6.0, 1.5, 0.0), (3.0, 1.5, 0.0)  # straight behind: no way for a Dubins car
    kernel, python = both(hybrid, start, goal, cm)
    assert kernel == python and kernel[0] == "NoValidPathCouldBeFound"
    hybrid = SmacPlannerHybrid(
        "GridBased",
        SmacPlannerHybrid.Params(
            motion_model_for_search="REEDS_SHEPP", terminal_checking_interval=7
        ),
    )
    kernel, python = both(hybrid, (1.0, 1.5, 0.0), (8.0, 1.5, math.pi), cm, cancel_after=4)
    assert kernel == python and kernel[0] == "PlannerCancelled" and kernel[1] > 0
    # a search that starts with room for 2 nodes and 1 cell grows as it goes
    monkeypatch.setattr(
        hybrid_kernel, "new_state", functools.partial(hybrid_kernel.new_state, nodes=2, blocks=1)
    )
    hybrid = SmacPlannerHybrid(
        "GridBased", SmacPlannerHybrid.Params(motion_model_for_search="REEDS_SHEPP")
    )
    kernel, python = both(hybrid, start, goal, cm)
    assert kernel == python and isinstance(kernel[0], bytes)


def test_node_arrays_read_as_the_searchs_tuples():
    s = hybrid_kernel.new_state(10, 4, nodes=4)
    s.node_f[:2] = [[1.5, 2.5, 0.0], [2.0, 3.0, 1.25]]
    s.node_i[:2] = [[3, -1, -1, 15], [1, 0, 2, 17]]
    s.counters[hybrid_kernel.N_NODES] = 2
    nodes = hybrid_kernel.NodeArrays(s)
    assert len(nodes) == 2 and nodes[1] == (2.0, 3.0, 1, 1.25, 0, 2, 17)
    assert all(type(v) in (int, float) for v in nodes[0])
    with pytest.raises(IndexError):
        nodes[2]


_COMPILE = """
from btnav.core.geometry import Pose2D
from btnav.planning import dubins_kernel, hybrid_kernel, reeds_shepp_kernel
from btnav.core import fmath_kernels
from btnav.planning.smac_planner_hybrid import SmacPlannerHybrid
from tests.planning.test_smac_planner_hybrid import corridor
for model in ("DUBIN", "REEDS_SHEPP"):
    SmacPlannerHybrid("G", SmacPlannerHybrid.Params(motion_model_for_search=model)).create_plan(
        Pose2D(2.0, 1.5, 0.0), Pose2D(8.0, 1.5, 0.0), corridor())
fmath_kernels.exp(0.5), fmath_kernels.log(0.5)
"""


def test_no_fused_multiply_add_in_the_kernels(fused_multiply_adds):
    """LLVM was not allowed to contract a * b + c anywhere."""
    kernels = (
        "hybrid_kernel.advance, reeds_shepp_kernel.solve_words, dubins_kernel.solve_words, "
        "reeds_shepp_kernel.sample_segments, fmath_kernels.exp, fmath_kernels.log"
    )
    n_chars, n_fused = fused_multiply_adds(_COMPILE, kernels)
    assert n_chars > 10_000 and n_fused == 0
