"""Nav2's FollowPath (MPPI) section validates unchanged; critic sections by each critic's Params."""

from __future__ import annotations

import pytest

from btnav.control.mppi import MPPIController, MPPIParams
from btnav.control.mppi.critics import CostCritic, PathAlignCritic
from btnav.core.errors import ParamsError
from btnav.params import load_params
from btnav.plugins import lookup


@pytest.fixture
def nav2_copy(tmp_path, nav2_params_file):
    """`nav2_copy(old, new)`: Nav2's file with the first line holding `old` edited; (path, line)."""

    def make(old: str, new: str):
        lines = nav2_params_file.read_text().splitlines(keepends=True)
        i = next(i for i, line in enumerate(lines) if old in line)
        lines[i] = lines[i].replace(old, new)
        out = tmp_path / "params.yaml"
        out.write_text("".join(lines))
        return out, i + 1

    return make


def test_nav2_follow_path_resolves_to_mppi(nav2_params_file):
    pf = load_params(nav2_params_file)
    section = pf.servers["controller_server"].plugin("FollowPath")
    assert section.cls is MPPIController
    assert lookup("controller", "nav2_mppi_controller::MPPIController") is MPPIController
    p = section.params
    assert isinstance(p, MPPIParams)
    assert (p.time_steps, p.model_dt, p.batch_size) == (56, 0.05, 2000)
    assert (p.vx_std, p.wz_std, p.temperature, p.gamma) == (0.2, 0.4, 0.3, 0.015)
    assert p.model_section().cls is lookup("motion_model", "mppi::DiffDriveMotionModel")
    assert p.trajectory_validator.collision_lookahead_time == 2.0
    cost = p.critic_sections["CostCritic"]
    assert isinstance(cost, CostCritic.Params)
    assert (cost.cost_weight, cost.critical_cost, cost.trajectory_point_step) == (3.81, 300.0, 2)
    assert isinstance(p.critic_sections["PathAlignCritic"], PathAlignCritic.Params)
    assert p.critic_sections["PathAngleCritic"].max_angle_to_furthest == 1.0
    # Visualisation keys are accepted and reported as ignored, not dropped silently.
    ignored = {e.key for e in pf.ignored}
    assert "controller_server.FollowPath.TrajectoryVisualizer" in ignored
    assert "controller_server.FollowPath.visualize" in ignored
    # The controller builds from it.
    controller = section.cls("FollowPath", p)
    assert [type(c).__name__ for c in controller.critics] == p.critics


def test_misspelt_critic_key_is_located(nav2_copy):
    path, line = nav2_copy("near_goal_distance: 1.0", "near_goal_distanse: 1.0")
    with pytest.raises(ParamsError) as info:
        load_params(path)
    err = info.value
    assert err.line == line
    assert err.key == "controller_server.FollowPath.CostCritic.near_goal_distanse"
    assert err.suggestion == "near_goal_distance"


def test_unknown_critic_suggests_close_name(nav2_copy):
    path, _ = nav2_copy('"GoalAngleCritic",', '"GoalAngelCritic",')
    with pytest.raises(ParamsError) as info:
        load_params(path)
    assert info.value.suggestion == "GoalAngleCritic"


def test_bad_critic_value_is_rejected(nav2_copy):
    path, line = nav2_copy("trajectory_point_step: 2", "trajectory_point_step: 0")
    with pytest.raises(ParamsError) as info:
        load_params(path)
    assert info.value.line == line
    assert info.value.key.endswith("CostCritic.trajectory_point_step")


def test_motion_model_section_and_legacy_spelling():
    p = MPPIParams.model_validate(
        {"motion_model": "omni", "omni": {"plugin": "mppi::OmniMotionModel"}}
    )
    assert MPPIController("x", p).model.holonomic
    p = MPPIParams.model_validate({"motion_model": "Ackermann"})
    assert MPPIController("x", p).model.min_turning_r == 0.2
    with pytest.raises(Exception, match="motion_model"):
        MPPIParams.model_validate({"motion_model": "tank"})


def test_motion_models_are_plugins_a_users_model_is_a_peer_of():
    from btnav.control.mppi.motion_models import OmniMotionModel
    from btnav.plugins import register, unregister

    @register("motion_model", "my_pkg::CrabMotionModel")
    class Crab(OmniMotionModel):
        class Params(OmniMotionModel.Params):
            sideways_only: bool = True

    try:
        p = MPPIParams.model_validate(
            {"motion_model": "crab", "crab": {"plugin": "my_pkg/CrabMotionModel"}}
        )
        model = MPPIController("x", p).model
        assert isinstance(model, Crab) and model.params.sideways_only and model.holonomic
    finally:
        unregister("motion_model", "my_pkg::CrabMotionModel")


def test_a_misspelt_motion_model_plugin_names_its_line_and_the_right_spelling(nav2_copy):
    path, line = nav2_copy('"mppi::DiffDriveMotionModel"', '"mppi::DifDriveMotionModel"')
    with pytest.raises(ParamsError) as info:
        load_params(path)
    assert info.value.line == line
    assert info.value.key == "controller_server.FollowPath.diff_drive.plugin"
    assert info.value.suggestion == "mppi::DiffDriveMotionModel"


def test_a_misspelt_motion_model_param_names_the_right_spelling(nav2_copy):
    path, line = nav2_copy(
        '"mppi::DiffDriveMotionModel"',
        '"mppi::AckermannMotionModel"\n        min_turning_radius: 0.5',
    )
    with pytest.raises(ParamsError) as info:
        load_params(path)
    assert info.value.line == line + 1
    assert info.value.key == "controller_server.FollowPath.diff_drive.min_turning_radius"
    assert info.value.suggestion == "min_turning_r"


def test_ackermanns_min_turning_r_reaches_the_model():
    p = MPPIParams.model_validate(
        {
            "motion_model": "ackermann",
            "ackermann": {"plugin": "mppi::AckermannMotionModel", "min_turning_r": 0.9},
        }
    )
    assert MPPIController("x", p).model.min_turning_r == 0.9


def test_unlisted_critic_section_is_ignored_not_an_error():
    p = MPPIParams.model_validate(
        {"critics": ["CostCritic"], "TwirlingCritic": {"cost_weight": 10.0}}
    )
    assert list(p.critic_sections) == ["CostCritic"]
