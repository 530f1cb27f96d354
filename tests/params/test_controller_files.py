"""Switching controllers: the shipped DWB and RPP params files, and the one-line message
when a section keeps another controller's keys under a new `plugin:`."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from btnav.cli import main
from btnav.cli.params import check_main
from btnav.control.regulated_pure_pursuit import NAV2_DOCS_SECTION
from btnav.core.errors import ParamsError
from btnav.params import load_params
from btnav.params.updates import apply_overrides

REPO = Path(__file__).resolve().parents[2]
PARAMS = REPO / "params"
MPPI = "nav2_mppi_controller::MPPIController"
DWB = "dwb_core::DWBLocalPlanner"
RPP = "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController"


def follow_path_line(path: Path) -> int:
    lines = path.read_text().splitlines()
    return next(n for n, line in enumerate(lines, 1) if line == "    FollowPath:")


@pytest.mark.parametrize(
    ("name", "plugin"), [("nav2_params_dwb.yaml", DWB), ("nav2_params_rpp.yaml", RPP)]
)
def test_shipped_controller_files_are_nav2s_file_but_for_followpath(
    name, plugin, nav2_params_file, capsys
):
    path = PARAMS / name
    assert path.read_text().startswith("# btnav: Nav2's own nav2_params.yaml")
    assert check_main(path) == 0
    assert f"FollowPath -> {plugin}" in capsys.readouterr().out
    ours, nav2 = yaml.safe_load(path.read_text()), yaml.safe_load(nav2_params_file.read_text())
    section = ours["controller_server"]["ros__parameters"].pop("FollowPath")
    nav2["controller_server"]["ros__parameters"].pop("FollowPath")
    assert ours == nav2
    assert section["plugin"] == plugin
    if plugin == RPP:
        assert section == NAV2_DOCS_SECTION
    else:  # Nav2's documented DWB section: its speeds and critics
        assert section["max_vel_x"] == 0.26 and section["BaseObstacle.scale"] == 0.02
        assert section["critics"][0] == "RotateToGoal" and len(section["critics"]) == 7


def test_run_with_dwb_over_mppis_keys_is_one_line_naming_mppi_and_the_fix(capsys):
    code = main(
        [
            "run",
            str(REPO / "missions" / "office_tour.yaml"),
            "--set",
            f"controller_server.FollowPath.plugin={DWB}",
        ]
    )
    assert code == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert captured.out == "" and len(err.splitlines()) == 1 and len(err) < 400
    line = follow_path_line(PARAMS / "nav2_params.yaml")
    assert err.startswith("btnav: error: ")
    assert f"nav2_params.yaml:{line}: controller_server.FollowPath: " in err
    assert f"this section holds {MPPI}'s keys (time_steps, " in err
    assert f"but its plugin is {DWB}: replace the section with DWB's (" in err
    assert "nav2_params_dwb.yaml has one) or set plugin back" in err


def test_mppi_over_dwbs_keys_names_dwb_and_points_to_nav2s_file():
    path = PARAMS / "nav2_params_dwb.yaml"
    with pytest.raises(ParamsError) as info:
        apply_overrides(load_params(path), {"controller_server.FollowPath.plugin": MPPI})
    err = info.value
    assert (err.file, err.line, err.key) == (
        str(path),
        follow_path_line(path),
        "controller_server.FollowPath",
    )
    assert err.message.startswith(f"this section holds {DWB}'s keys (debug_trajectory_details, ")
    assert "replace the section with MPPI's (" in err.message
    assert "nav2_params.yaml has one)" in err.message


def test_a_single_key_of_another_controller_is_still_an_unknown_key():
    """One stray key is a typo or a slip, reported as such, not as a switched section."""
    path = PARAMS / "nav2_params_dwb.yaml"
    with pytest.raises(ParamsError) as info:
        apply_overrides(load_params(path), {"controller_server.FollowPath.lookahead_dist": 0.6})
    assert info.value.message.startswith("unknown key 'lookahead_dist'")
    assert "this section holds" not in info.value.message
