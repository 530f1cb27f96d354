"""The dock database: Nav2's dock file and the params' `docks:` sections, mistakes located."""

from __future__ import annotations

import pytest

from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D
from btnav.docking.dock_database import DockDatabase, dock_from, load_dock_file
from btnav.docking.exceptions import DockNotInDB, DockNotValid
from btnav.docking.simple_charging_dock import SimpleChargingDock
from btnav.params.docking import DockInstance
from btnav.params.loader import load_params

NAV2_DOCK_FILE = """\
docks:
  home_dock:
    type: "simple_charging_dock"
    frame: map
    pose: [0.3, 0.0, 0.0]
  flex_dock1:
    type: "nova_carter_dock"
    pose: [10.0, 10.0, 0.0]
    id: "c67f50cb-e152-4720-85cc-5eb20bd85ce8"
"""


def write(tmp_path, text, name="docks.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_nav2s_dock_file_reads_as_nav2_reads_it(tmp_path):
    docks = load_dock_file(write(tmp_path, NAV2_DOCK_FILE))
    assert list(docks) == ["home_dock", "flex_dock1"]
    assert docks["home_dock"].pose == Pose2D(0.3, 0.0, 0.0)
    assert docks["flex_dock1"].frame == "map"  # the default
    assert docks["flex_dock1"].id == "c67f50cb-e152-4720-85cc-5eb20bd85ce8"


def test_a_misspelt_key_is_an_error_at_its_line_with_the_right_spelling(tmp_path):
    path = write(tmp_path, NAV2_DOCK_FILE.replace("    frame: map", "    fram: map"))
    with pytest.raises(ParamsError) as info:
        load_dock_file(path)
    err = info.value
    assert err.file == str(path) and err.line == 4
    assert err.key == "docks.home_dock.fram" and err.suggestion == "frame"
    assert "did you mean 'frame'" in str(err)


def test_a_pose_of_two_numbers_and_a_missing_type_are_errors(tmp_path):
    with pytest.raises(ParamsError, match=r"\[x, y, yaw\], got 2") as info:
        load_dock_file(write(tmp_path, NAV2_DOCK_FILE.replace("[0.3, 0.0, 0.0]", "[0.3, 0.0]")))
    assert info.value.line == 5
    with pytest.raises(ParamsError, match="type"):
        load_dock_file(
            write(tmp_path, NAV2_DOCK_FILE.replace('    type: "nova_carter_dock"\n', ""))
        )
    with pytest.raises(ParamsError, match="holds 'docks:'") as info:
        load_dock_file(write(tmp_path, "dokcs: {}\n"))
    assert info.value.suggestion == "docks"


def test_a_type_that_is_no_dock_plugin_names_the_closest(tmp_path):
    path = write(tmp_path, NAV2_DOCK_FILE.replace("nova_carter_dock", "simple_chargin_dock"))
    with pytest.raises(ParamsError) as info:
        load_dock_file(path, ["simple_charging_dock"])
    assert info.value.line == 7 and info.value.suggestion == "simple_charging_dock"


def test_docks_in_the_params_file(nav2_params_file, tmp_path):
    text = nav2_params_file.read_text()
    given = text.replace(
        "    # docks: ['home_dock']  # Input your docks here\n"
        "    # home_dock:\n"
        "    #   type: 'simple_charging_dock'\n"
        "    #   frame: map\n"
        "    #   pose: [0.0, 0.0, 0.0]\n",
        "    docks: ['home_dock']\n"
        "    home_dock:\n"
        "      type: 'simple_chargng_dock'\n"
        "      pose: [1.0, 2.0, 0.5]\n",
    )
    assert given != text
    with pytest.raises(ParamsError) as info:
        load_params(write(tmp_path, given, "nav2_params.yaml"))
    assert info.value.key == "docking_server.home_dock.type"
    assert info.value.suggestion == "simple_charging_dock"
    fixed = load_params(write(tmp_path, given.replace("chargng", "charging"), "fixed.yaml"))
    home = fixed.server("docking_server").model.dock_sections["home_dock"]
    assert home.pose == [1.0, 2.0, 0.5] and home.frame == "map"


def test_finding_a_dock_fails_as_nav2_does():
    plugin = SimpleChargingDock("simple_charging_dock")
    db = DockDatabase(
        {"simple_charging_dock": plugin},
        {
            "home_dock": dock_from(DockInstance(type="simple_charging_dock", pose=[1, 2, 0])),
            "old_dock": dock_from(DockInstance(type="removed_plugin", pose=[0, 0, 0])),
        },
    )
    assert db.find_dock("home_dock").plugin is plugin
    with pytest.raises(DockNotInDB, match="did you mean 'home_dock'"):
        db.find_dock("home_dok")
    with pytest.raises(DockNotValid):
        db.find_dock("old_dock")
    assert db.find_dock_plugin("") is plugin  # the only plugin there is
