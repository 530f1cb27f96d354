"""A broken description is one error naming the user's file and the line to fix."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.cli import main
from btnav.core.errors import BtnavError
from btnav.description import load_description

HEAD = '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'


def write(folder: Path, name: str, body: str) -> Path:
    path = folder / name
    path.write_text(HEAD + body + "</robot>\n")
    return path


def line_of(path: Path, text: str) -> int:
    """The 1-based line of `text` in the file (where the error must point)."""
    return next(i for i, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def failure(path: Path, **kwargs: object) -> BtnavError:
    with pytest.raises(BtnavError) as info:
        load_description(path, **kwargs)  # type: ignore[arg-type]
    return info.value


def test_a_joint_to_a_missing_link(tmp_path):
    path = write(
        tmp_path,
        "r.urdf",
        '  <link name="base_link"/>\n  <link name="wheel"/>\n'
        '  <joint name="wheel_joint" type="continuous">\n'
        '    <parent link="base_link"/>\n    <child link="wheeel"/>\n  </joint>\n',
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "<joint"))
    assert "joint 'wheel_joint'" in err.message and "'wheeel' is not defined" in err.message
    assert err.suggestion == "wheel"


def test_a_joint_in_a_macro_names_the_macro_s_line_and_the_call(tmp_path):
    path = write(
        tmp_path,
        "r.urdf.xacro",
        '  <xacro:macro name="wheel" params="side">\n'
        '    <joint name="${side}_joint" type="continuous">\n'
        '      <parent link="base_link"/>\n      <child link="${side}_whel"/>\n'
        "    </joint>\n  </xacro:macro>\n"
        '  <link name="base_link"/>\n  <link name="left_wheel"/>\n'
        '  <xacro:wheel side="left"/>\n',
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "<joint"))
    assert "'left_whel' is not defined" in err.message and err.suggestion == "left_wheel"


def test_an_unknown_macro(tmp_path):
    path = write(
        tmp_path,
        "r.urdf.xacro",
        '  <xacro:macro name="wheel" params="side"><link name="${side}"/></xacro:macro>\n'
        '  <link name="base_link"/>\n'
        '  <xacro:wheel side="a"/>\n'
        '  <xacro:wheal side="b"/>\n',
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "xacro:wheal"))
    assert "unknown xacro macro 'wheal'" in err.message and err.suggestion == "wheel"


def test_an_unknown_macro_in_an_included_file_names_that_file(tmp_path):
    (tmp_path / "parts").mkdir()
    part = write(
        tmp_path / "parts", "parts.xacro", '  <link name="base_link"/>\n  <xacro:lidar/>\n'
    )
    path = write(tmp_path, "r.urdf.xacro", '  <xacro:include filename="parts/parts.xacro"/>\n')
    err = failure(path)
    assert Path(err.file or "").resolve() == part.resolve()
    assert err.line == line_of(part, "xacro:lidar")
    assert "unknown xacro macro 'lidar'" in err.message
    assert f"included at {path}:{line_of(path, 'xacro:include')}" in err.message


def test_an_include_that_cannot_be_found(tmp_path):
    path = write(
        tmp_path,
        "r.urdf.xacro",
        '  <link name="base_link"/>\n\n  <xacro:include filename="$(find btnav_robots)/nowhere.xacro"/>\n',
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "xacro:include"))
    assert "cannot include '$(find btnav_robots)/nowhere.xacro'" in err.message
    assert "nowhere.xacro" in err.message


def test_a_package_no_path_knows(tmp_path):
    path = write(
        tmp_path,
        "r.urdf.xacro",
        '  <link name="base_link"/>\n  <xacro:include filename="$(find my_robot)/parts.xacro"/>\n',
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "xacro:include"))
    assert "package 'my_robot' not found" in err.message and "--package my_robot=DIR" in err.message


def test_a_malformed_number(tmp_path):
    path = write(
        tmp_path,
        "r.urdf.xacro",
        '  <xacro:property name="r" value="0.1"/>\n'
        '  <link name="base_link">\n    <collision>\n'
        '      <origin xyz="0 0 0.1o"/>\n'
        '      <geometry><cylinder radius="${r}" length="0.1"/></geometry>\n'
        "    </collision>\n  </link>\n",
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "<origin"))
    assert "malformed number '0.1o' in origin xyz" in err.message


def test_a_malformed_number_in_a_lidar_block(tmp_path):
    path = write(
        tmp_path,
        "r.urdf",
        '  <link name="base_link"/>\n  <gazebo reference="base_link">\n'
        '    <sensor type="ray" name="lidar"><ray><scan><horizontal>\n'
        "      <samples>3six0</samples>\n"
        "    </horizontal></scan><range><max>8</max></range></ray></sensor>\n  </gazebo>\n",
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "<samples>"))
    assert "malformed number '3six0'" in err.message


def test_an_undefined_property_names_its_line_and_the_close_one(tmp_path):
    path = write(
        tmp_path,
        "r.urdf.xacro",
        '  <xacro:property name="wheel_radius" value="0.05"/>\n'
        '  <link name="base_link">\n    <collision><geometry>\n'
        '      <cylinder radius="${wheel_radius}" length="${wheel_radiuss}"/>\n'
        "    </geometry></collision>\n  </link>\n",
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "<cylinder"))
    assert "'wheel_radiuss' is not defined" in err.message and err.suggestion == "wheel_radius"


def test_a_xacro_arg_without_a_value(tmp_path):
    path = write(tmp_path, "r.urdf.xacro", '  <link name="$(arg prefix)base_link"/>\n')
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "<link"))
    assert "xacro arg 'prefix' has no value" in err.message
    assert load_description(path, args={"prefix": "tb3_"}).base_frame == "tb3_base_link"


def test_xml_that_is_not_well_formed(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text('<robot name="r">\n  <link name="a">\n</robot>\n')
    err = failure(path)
    assert (err.file, err.line) == (str(path), 3)
    assert "not well-formed XML: mismatched tag" in err.message


def test_the_cli_prints_one_located_line_and_exits_2(tmp_path, capsys):
    path = write(tmp_path, "r.urdf.xacro", '  <link name="base_link"/>\n  <xacro:nope/>\n')
    assert main(["robot", "show", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"btnav: error: {path}:{line_of(path, 'xacro:nope')}: unknown xacro macro 'nope'"
    ]


def test_a_sensor_on_a_link_that_is_not_there(tmp_path):
    path = write(
        tmp_path,
        "r.urdf",
        '  <link name="base_link"/>\n  <link name="base_scan"/>\n'
        '  <joint name="j" type="fixed"><parent link="base_link"/><child link="base_scan"/></joint>\n'
        '  <gazebo reference="base_scna">\n'
        '    <sensor type="ray" name="lds"/>\n  </gazebo>\n',
    )
    err = failure(path)
    assert (err.file, err.line) == (str(path), line_of(path, "<gazebo"))
    assert "no link 'base_scna' to mount the sensor 'lds' on" in err.message
    assert err.suggestion == "base_scan"
