"""`model://NAME` found as Gazebo finds it: model_paths, GZ_SIM_RESOURCE_PATH, GAZEBO_MODEL_PATH."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from btnav.core.errors import BtnavError, WorldError
from btnav.description import load_description
from btnav.sim.world import World

from .gazebo_models import box_link, line_of, write_model
from .test_world_description import office_world


def robot(root: Path, name: str, size: str = "0.4 0.3 0.1") -> Path:
    return write_model(root, name, box_link("base_link", size))


def width(d) -> float:
    ys = [y for _, y in d.footprint.polygon]
    return round(max(ys) - min(ys), 6)


def test_model_paths_find_the_model_and_its_model_config_picks_the_file(tmp_path):
    robot(tmp_path / "models", "bot")
    d = load_description("model://bot", model_paths=[tmp_path / "models"])
    assert d.kind == "sdf" and d.file == str(tmp_path / "models" / "bot" / "model.sdf")
    assert width(d) == 0.3


def test_each_environment_variable_is_searched_colon_separated(tmp_path, monkeypatch):
    robot(tmp_path / "gz", "gzbot", "0.4 0.5 0.1")
    robot(tmp_path / "classic", "classicbot", "0.4 0.7 0.1")
    with pytest.raises(BtnavError, match="model://gzbot not found"):
        load_description("model://gzbot")
    monkeypatch.setenv("GZ_SIM_RESOURCE_PATH", f"{tmp_path / 'empty'}:{tmp_path / 'gz'}")
    assert width(load_description("model://gzbot")) == 0.5
    monkeypatch.setenv("GAZEBO_MODEL_PATH", f"{tmp_path / 'nothing'}:{tmp_path / 'classic'}")
    assert width(load_description("model://classicbot")) == 0.7


def test_model_paths_come_before_the_environment_and_gz_before_classic(tmp_path, monkeypatch):
    for folder, size in (
        ("given", "0.4 0.1 0.1"),
        ("gz", "0.4 0.2 0.1"),
        ("classic", "0.4 0.3 0.1"),
    ):
        robot(tmp_path / folder, "bot", size)
    monkeypatch.setenv("GZ_SIM_RESOURCE_PATH", str(tmp_path / "gz"))
    monkeypatch.setenv("GAZEBO_MODEL_PATH", str(tmp_path / "classic"))
    assert width(load_description("model://bot", model_paths=[tmp_path / "given"])) == 0.1
    assert width(load_description("model://bot")) == 0.2
    monkeypatch.delenv("GZ_SIM_RESOURCE_PATH")
    assert width(load_description("model://bot")) == 0.3


def test_model_config_picks_the_newest_sdf_the_parser_reads(tmp_path):
    folder = tmp_path / "bot"
    robot(tmp_path, "bot")
    (folder / "model-1_4.sdf").write_text((folder / "model.sdf").read_text())
    (folder / "model-future.sdf").write_text("not even XML")
    (folder / "model.config").write_text(
        '<model><name>bot</name><sdf version="1.4">model-1_4.sdf</sdf>'
        '<sdf version="1.9">model.sdf</sdf><sdf version="1.99">model-future.sdf</sdf></model>'
    )
    assert load_description(folder).file == str(folder / "model.sdf")
    (folder / "model.config").write_text(
        '<model><sdf version="1.4">model-1_4.sdf</sdf><sdf version="1.5">model.sdf</sdf></model>'
    )
    assert load_description(folder).file == str(folder / "model.sdf")
    (folder / "model.config").write_text('<model><sdf version="1.6">gone.sdf</sdf></model>')
    with pytest.raises(BtnavError, match=r"model.config names gone.sdf") as info:
        load_description(folder)
    assert info.value.file == str(folder / "model.config")


def test_an_include_finds_a_model_beside_the_description_s_own_folder(tmp_path):
    """A checkout's models/robot/model.sdf reads models/parts/ with no path set."""
    write_model(tmp_path / "models", "parts", box_link("base_link", "0.2 0.6 0.1"))
    main = write_model(
        tmp_path / "models", "robot", "    <include><uri>model://parts</uri></include>\n"
    )
    d = load_description(main)
    assert d.base_frame == "parts::base_link" and width(d) == 0.6


def test_a_missing_include_names_the_uri_s_line_and_every_folder_searched(tmp_path, monkeypatch):
    write_model(tmp_path / "models", "lidar_2d", box_link("link"))
    monkeypatch.setenv("GZ_SIM_RESOURCE_PATH", str(tmp_path / "gz"))
    main = write_model(
        tmp_path / "robots",
        "bot",
        box_link("base_link")
        + "    <include>\n      <uri>model://lidar_2b</uri>\n    </include>\n",
    )
    with pytest.raises(BtnavError) as info:
        load_description(main, model_paths=[tmp_path / "models"])
    err = info.value
    assert (err.file, err.line) == (str(main), line_of(main, "model://lidar_2b"))
    assert err.message.startswith("model://lidar_2b not found: no model folder lidar_2b/")
    assert f"{tmp_path / 'models'} (model_paths)" in err.message
    assert f"{tmp_path / 'gz'} (GZ_SIM_RESOURCE_PATH)" in err.message
    assert f"{tmp_path / 'robots'} (beside the description)" in err.message
    assert "GAZEBO_MODEL_PATH is not set" in err.message
    assert err.suggestion == "lidar_2d"


def test_a_model_path_that_is_not_a_folder_is_the_users_to_fix(tmp_path):
    with pytest.raises(BtnavError, match=r"model path .*nowhere is not a folder"):
        load_description("model://bot", model_paths=[tmp_path / "nowhere"])


def test_a_world_reads_model_uri_through_its_model_paths(tmp_path):
    robot(tmp_path / "models", "bot", "0.4 0.36 0.1")
    world = office_world(
        tmp_path,
        {
            "description": "model://bot",
            "model_paths": ["../models"],
            "pose": [1, 1, 0],
            "sensors": [],
        },
    )
    spec = World.from_file(world).spec.robot
    assert spec.description.name == "bot"
    assert max(y for _, y in spec.footprint.polygon) == pytest.approx(0.18)


def test_a_world_s_missing_model_is_its_error_at_the_description_line(tmp_path):
    robot(tmp_path / "models", "burger")
    world = office_world(
        tmp_path,
        {"description": "model://burgr", "model_paths": ["../models"], "pose": [1, 1, 0]},
    )
    with pytest.raises(WorldError) as info:
        World.from_file(world)
    err = info.value
    assert (err.file, err.line) == (str(world), line_of(world, "description:"))
    assert "model://burgr not found" in err.message and err.suggestion == "burger"
    assert f"{tmp_path / 'models'} (model_paths)" in err.message


def test_a_world_s_model_path_that_is_not_there_is_named_at_its_line(tmp_path):
    robot(tmp_path / "models", "bot")
    world = office_world(
        tmp_path,
        {"description": "model://bot", "model_paths": ["../modles"], "pose": [1, 1, 0]},
    )
    with pytest.raises(WorldError) as info:
        World.from_file(world)
    assert info.value.line == line_of(world, "model_paths:")
    assert "modles is not a folder" in info.value.message
    doc = yaml.safe_load(world.read_text())
    doc["robot"]["model_paths"] = "../models"
    world.write_text(yaml.safe_dump(doc))
    with pytest.raises(WorldError, match=r"model_paths lists the folders"):
        World.from_file(world)
