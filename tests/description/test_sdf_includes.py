"""SDF includes and nested models: overrides, scoped names, poses composed, relative_to honoured."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from btnav.core.errors import BtnavError, BtnavWarning
from btnav.description import load_description

from .gazebo_models import LIDAR, box_link, line_of, write_model

WHEEL = """    <pose>1 2 3 0 0 0</pose>
    <link name="wheel">
      <collision name="c"><geometry>
        <cylinder><radius>0.05</radius><length>0.02</length></cylinder>
      </geometry></collision>
    </link>
"""


def wheel_joint(side: str, y: float) -> str:
    # The joint frame is placed relative to base_link (relative to its child, the wheel
    # rolled one way or the other, the wheels would sit 0.2 m apart), and rolled so that
    # its own y points down: the axis, expressed in the model frame, is still sideways.
    return f"""    <joint name="{side}_wheel_joint" type="revolute">
      <parent>base_link</parent><child>{side}_wheel::wheel</child>
      <pose relative_to="base_link">0 {y} 0.05 -1.5707963267948966 0 0</pose>
      <axis><xyz expressed_in="__model__">0 1 0</xyz></axis>
    </joint>
"""


def wheel_include(side: str, y: float) -> str:
    roll = math.copysign(math.pi / 2, y)  # mirrored wheels, as descriptions often have
    return f"""    <include>
      <uri>model://wheel</uri>
      <name>{side}_wheel</name>
      <pose>0 {y} 0.05 {roll} 0 0</pose>
    </include>
"""


def test_includes_take_the_include_s_name_and_pose_and_drive_as_wheels(tmp_path):
    write_model(tmp_path, "wheel", WHEEL)
    main = write_model(
        tmp_path,
        "bot",
        box_link("base_link")
        + wheel_include("left", 0.15)
        + wheel_include("right", -0.15)
        + wheel_joint("left", 0.15)
        + wheel_joint("right", -0.15),
    )
    d = load_description(main)
    left = d.frame("left_wheel::wheel")  # the include's <name>, not the file's "wheel"
    assert (left.x, left.y, left.z) == pytest.approx((0.0, 0.15, 0.05))  # not 1 2 3
    assert d.frame("right_wheel::wheel").y == pytest.approx(-0.15)
    assert left.parent == "base_link"
    assert d.drive is not None and d.drive.name == "diff_drive"
    assert d.drive.wheel_separation == pytest.approx(0.3)
    assert d.drive.wheel_radius == pytest.approx(0.05)


def test_two_includes_of_one_model_without_names_collide_at_the_second(tmp_path):
    write_model(tmp_path, "wheel", WHEEL)
    inc = "    <include><uri>model://wheel</uri></include>\n"
    main = write_model(tmp_path, "bot", box_link("base_link") + inc + inc)
    with pytest.raises(BtnavError, match=r"link 'wheel::wheel' is defined twice") as info:
        load_description(main)
    wheel = tmp_path / "wheel" / "model.sdf"  # the link's own line, in the included file
    assert (info.value.file, info.value.line) == (str(wheel), line_of(wheel, "<link"))


NESTED = f"""{box_link("base_link")}    <model name="mast">
      <pose>0.1 0 0.2 0 0 1.5707963267948966</pose>
      <link name="post"><pose>0.05 0 0 0 0 0</pose></link>
      <frame name="top" attached_to="post"><pose>0 0 0.3 0 0 0</pose></frame>
      <link name="scanner">
        <pose relative_to="top">0.02 0 0 0 0 0</pose>
{LIDAR.format(name="lidar", pose='<pose relative_to="post">0 0 0.35 0 0 0</pose>')}
      </link>
      <joint name="post_to_scanner" type="fixed"><parent>post</parent><child>scanner</child></joint>
    </model>
    <joint name="mast_joint" type="fixed"><parent>base_link</parent><child>mast</child></joint>
"""


def test_nested_models_compose_their_poses_and_honour_relative_to(tmp_path):
    d = load_description(write_model(tmp_path, "bot", NESTED))
    # the mast's frame is 0.1 ahead, 0.2 up, turned 90 degrees: its x is the robot's y
    post = d.frame("mast::post")
    assert (post.x, post.y, post.z, post.yaw) == pytest.approx((0.1, 0.05, 0.2, math.pi / 2))
    scanner = d.frame("mast::scanner")  # relative_to the frame 'top', 0.3 above the post
    assert (scanner.x, scanner.y, scanner.z) == pytest.approx((0.1, 0.07, 0.5))
    assert scanner.parent == "mast::post"
    (lidar,) = d.lidars  # the sensor's pose relative_to 'post', another link
    assert lidar.link == "mast::scanner" and lidar.frame == "mast::scanner"
    assert lidar.pose == pytest.approx((0.1, 0.05, math.pi / 2)) and lidar.z == pytest.approx(0.55)
    # `<child>mast</child>`: a joint to a nested model joins its canonical (first) link
    assert post.parent == "base_link"


def test_an_include_pose_relative_to_a_frame_of_the_including_model(tmp_path):
    write_model(
        tmp_path,
        "sensor",
        f'    <link name="link">{LIDAR.format(name="s", pose="")}\n    </link>\n',
    )
    main = write_model(
        tmp_path,
        "bot",
        box_link("base_link")
        + '    <frame name="mount" attached_to="base_link"><pose>0.2 0 0.1 0 0 3.141592653589793</pose></frame>\n'
        + "    <include><uri>model://sensor</uri>\n"
        + '      <pose relative_to="mount">0.05 0 0 0 0 0</pose></include>\n'
        + '    <joint name="j" type="fixed"><parent>base_link</parent><child>sensor::link</child></joint>\n',
    )
    (lidar,) = load_description(main).lidars
    # 0.05 along the mount's x, which points backwards
    assert lidar.pose == pytest.approx((0.15, 0.0, math.pi)) and lidar.z == pytest.approx(0.1)


def test_a_merge_include_puts_the_links_in_the_including_model(tmp_path):
    write_model(tmp_path, "caster", '    <link name="caster"><pose>0.01 0 0 0 0 0</pose></link>\n')
    main = write_model(
        tmp_path,
        "bot",
        box_link("base_link")
        + '    <include merge="true"><uri>model://caster</uri><pose>-0.15 0 0 0 0 0</pose></include>\n'
        + '    <joint name="j" type="ball"><parent>base_link</parent><child>caster</child></joint>\n',
    )
    caster = load_description(main).frame("caster")  # no "caster::" scope
    assert caster.x == pytest.approx(-0.14)


def test_a_relative_to_that_names_nothing_is_located_with_a_suggestion(tmp_path):
    main = write_model(tmp_path, "bot", NESTED.replace('relative_to="top"', 'relative_to="tpo"'))
    with pytest.raises(BtnavError) as info:
        load_description(main)
    assert info.value.line == line_of(main, 'relative_to="tpo"')
    assert "relative_to 'mast::tpo' names no link" in info.value.message
    assert info.value.suggestion == "mast::top"


STATIC_PART = "    <static>true</static>\n" + box_link("cone", "0.1 0.1 0.3")


def test_a_static_include_no_joint_joins_is_left_out_with_a_warning(tmp_path):
    write_model(tmp_path, "cone", STATIC_PART)
    main = write_model(
        tmp_path, "bot", box_link("base_link") + "    <include><uri>model://cone</uri></include>\n"
    )
    with pytest.warns(BtnavWarning, match=r"nested model 'cone' is <static>") as caught:
        d = load_description(main)
    assert [f.name for f in d.frames] == ["base_link"]
    cone = tmp_path / "cone" / "model.sdf"
    (w,) = [c.message for c in caught if "static" in str(c.message)]
    assert (w.file, w.line) == (str(cone), line_of(cone, "<static>"))


def test_an_include_s_static_overrides_the_model_s_own(tmp_path):
    write_model(tmp_path, "cone", STATIC_PART)
    main = write_model(
        tmp_path,
        "bot",
        box_link("base_link")
        + "    <include><uri>model://cone</uri><static>false</static></include>\n"
        + '    <joint name="j" type="fixed"><parent>base_link</parent><child>cone::cone</child></joint>\n',
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = load_description(main)
    assert "cone::cone" in {f.name for f in d.frames}
    # and the other way round: a robot included as static is no robot
    with pytest.raises(BtnavError, match=r"model 'cone' is <static>: Gazebo holds it in place"):
        load_description(tmp_path / "cone")


FUEL = "https://fuel.gazebosim.org/1.0/OpenRobotics/models/{}"


def test_fuel_includes_nothing_refers_to_are_dropped_silently(tmp_path):
    main = write_model(
        tmp_path,
        "bot",
        f"    <include><uri>{FUEL.format('Ground Plane')}</uri></include>\n"
        f"    <include><uri>{FUEL.format('Sun')}</uri></include>\n" + box_link("base_link"),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = load_description(main)
    assert [f.name for f in d.frames] == ["base_link"]
    assert np.allclose(sorted(d.footprint.polygon)[0], (-0.2, -0.15))


@pytest.mark.parametrize(
    ("include", "child"),
    [
        (f"<uri>{FUEL.format('Hokuyo')}</uri>", "Hokuyo::link"),
        (f"<uri>{FUEL.format('Hokuyo/3')}</uri><name>front_lidar</name>", "front_lidar::link"),
    ],
)
def test_a_fuel_include_the_robot_needs_is_one_error_at_its_line(tmp_path, include, child):
    main = write_model(
        tmp_path,
        "bot",
        box_link("base_link")
        + f"    <include>\n      {include}\n    </include>\n"
        + f'    <joint name="lidar_joint" type="fixed"><parent>base_link</parent><child>{child}</child></joint>\n',
    )
    with pytest.raises(BtnavError) as info:
        load_description(main)
    err = info.value
    assert (err.file, err.line) == (str(main), line_of(main, "<include>"))
    assert FUEL.format("Hokuyo") in err.message
    assert "btnav reads nothing from the network" in err.message
    assert (
        f"joint 'lidar_joint' at {main}:{line_of(main, '<joint')} attaches '{child}'" in err.message
    )


def test_a_model_made_only_of_a_fuel_include_names_it(tmp_path):
    main = write_model(
        tmp_path, "bot", f"    <include><uri>{FUEL.format('X1 UGV')}</uri></include>\n"
    )
    with pytest.raises(BtnavError, match=r"needs the model at .*X1 UGV \(the model has no links"):
        load_description(main)


def test_an_include_loop_is_named(tmp_path):
    write_model(
        tmp_path, "a", box_link("base_link") + "    <include><uri>model://b</uri></include>\n"
    )
    b = write_model(tmp_path, "b", "    <include><uri>model://a</uri></include>\n")
    with pytest.raises(
        BtnavError, match=r"the includes form a loop: model.sdf -> model.sdf"
    ) as info:
        load_description(tmp_path / "a")
    assert (info.value.file, info.value.line) == (str(b), line_of(b, "<include>"))


def test_an_include_by_relative_path_and_a_sun_light_model(tmp_path):
    (tmp_path / "sun").mkdir()
    (tmp_path / "sun" / "model.config").write_text(
        "<model><sdf version='1.6'>model.sdf</sdf></model>"
    )
    (tmp_path / "sun" / "model.sdf").write_text(
        '<sdf version="1.6"><light name="sun" type="directional"/></sdf>'
    )
    write_model(tmp_path / "parts", "body", box_link("base_link", "0.5 0.5 0.1"))
    main = write_model(
        tmp_path,
        "bot",
        "    <include><uri>model://sun</uri></include>\n"
        "    <include><uri>../parts/body</uri><name>b</name></include>\n",
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = load_description(main)
    assert d.base_frame == "b::base_link"
    assert max(x for x, _ in d.footprint.polygon) == pytest.approx(0.25)


def test_a_wrapper_model_s_robot_base_is_btnav_s_base(tmp_path):
    write_model(
        tmp_path,
        "robot",
        '    <link name="base_footprint"/>\n'
        + box_link("base_link")
        + '    <link name="laser"><pose>0.1 0 0.2 0 0 0</pose></link>\n'
        + '    <joint name="b" type="fixed"><parent>base_footprint</parent><child>base_link</child></joint>\n'
        + '    <joint name="l" type="fixed"><parent>base_link</parent><child>laser</child></joint>\n',
    )
    main = write_model(
        tmp_path,
        "world_bits",
        "    <include><uri>model://robot</uri><name>tb</name><pose>3 4 0 0 0 1</pose></include>\n",
    )
    d = load_description(main)
    assert d.base_frame == "tb::base_footprint"
    assert d.footprint is not None and d.footprint.link == "tb::base_link"
    # the included robot's base_link is btnav's: its links hang from btnav's base_link
    edges = {child: (parent, pose) for parent, child, pose in d.tf_edges()}
    assert "tb::base_link" not in edges
    assert edges["tb::laser"] == ("base_link", pytest.approx((0.1, 0.0, 0.0)))


def test_a_placement_frame_puts_that_frame_at_the_include_s_pose(tmp_path):
    """SDF 1.8: `<placement_frame>` names the included model's frame its `<pose>` places;
    the model's own frame follows (its link 0.2 m ahead of and turned from the origin)."""
    write_model(
        tmp_path,
        "sensor",
        '    <link name="link"><pose>0.2 0 0 0 0 1.5707963267948966</pose>'
        f"{LIDAR.format(name='s', pose='')}\n    </link>\n",
    )
    main = write_model(
        tmp_path,
        "bot",
        box_link("base_link")
        + "    <include><uri>model://sensor</uri><placement_frame>link</placement_frame>\n"
        + "      <pose>0.1 0.05 0.3 0 0 0</pose></include>\n"
        + '    <joint name="j" type="fixed"><parent>base_link</parent><child>sensor::link</child></joint>\n',
    )
    d = load_description(main)
    (lidar,) = d.lidars
    assert lidar.pose == pytest.approx((0.1, 0.05, 0.0)) and lidar.z == pytest.approx(0.3)
    origin = d.frame("sensor::link")
    assert (origin.x, origin.y) == pytest.approx((0.1, 0.05))


def test_a_placement_frame_that_names_nothing_is_located(tmp_path):
    write_model(tmp_path, "sensor", '    <link name="link"/>\n')
    main = write_model(
        tmp_path,
        "bot",
        box_link("base_link")
        + "    <include><uri>model://sensor</uri><placement_frame>lnk</placement_frame>\n"
        + "      <pose>0.1 0 0 0 0 0</pose></include>\n"
        + '    <joint name="j" type="fixed"><parent>base_link</parent><child>sensor::link</child></joint>\n',
    )
    with pytest.raises(BtnavError) as info:
        load_description(main)
    err = info.value
    assert err.file == str(main) and err.line == line_of(main, "<placement_frame>")
    assert "placement_frame 'sensor::lnk'" in err.message and err.suggestion == "sensor::link"
