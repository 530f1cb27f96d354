"""The plugin registry: Nav2 spellings, user plugins as peers, did-you-mean."""

from __future__ import annotations

import textwrap

import pytest

from btnav import plugins
from btnav.core.errors import PluginError


@pytest.fixture
def straight_line():
    @plugins.register(
        "planner", "btnav/StraightLine", aliases=["nav2_straightline_planner/StraightLine"]
    )
    class StraightLine:
        pass

    yield StraightLine
    plugins.unregister("planner", "btnav/StraightLine")


def test_both_nav2_spellings_find_the_plugin(straight_line):
    for name in (
        "btnav/StraightLine",
        "btnav::StraightLine",
        "nav2_straightline_planner/StraightLine",
        "nav2_straightline_planner::StraightLine",
    ):
        assert plugins.lookup("planner", name) is straight_line
    assert straight_line.plugin_name == "btnav/StraightLine"
    assert "btnav/StraightLine" in plugins.names("planner")
    assert "nav2_straightline_planner/StraightLine" not in plugins.names("planner")
    assert "nav2_straightline_planner/StraightLine" in plugins.names("planner", aliases=True)


def test_unknown_name_suggests_the_close_one(straight_line):
    with pytest.raises(PluginError) as info:
        plugins.lookup("planner", "btnav/StraigthLine")
    assert info.value.suggestion == "btnav/StraightLine"
    assert "btnav/StraightLine" in str(info.value)


def test_unknown_kind_is_an_error():
    with pytest.raises(PluginError) as info:
        plugins.lookup("planer", "x")
    assert info.value.suggestion == "planner"


def test_unregister_drops_aliases(straight_line):
    plugins.unregister("planner", "btnav/StraightLine")
    assert not plugins.is_registered("planner", "nav2_straightline_planner::StraightLine")


def test_a_users_file_registers_a_peer(tmp_path):
    (tmp_path / "my_controller.py").write_text(
        textwrap.dedent(
            """
            from btnav.plugins import register

            @register("controller", "my_pkg/Wiggle")
            class Wiggle:
                pass
            """
        )
    )
    try:
        plugins.load_plugins(["my_controller.py"], tmp_path)
        assert plugins.lookup("controller", "my_pkg::Wiggle").__name__ == "Wiggle"
    finally:
        plugins.unregister("controller", "my_pkg/Wiggle")


def test_missing_plugin_module_or_file_is_a_user_error(tmp_path):
    with pytest.raises(PluginError, match="not found"):
        plugins.load_plugins(["nope_not_a_module_xyz"], tmp_path)
    with pytest.raises(PluginError, match="not found"):
        plugins.load_plugins(["plugins/missing.py"], tmp_path)
    (tmp_path / "broken.py").write_text("def f(:\n")
    with pytest.raises(PluginError, match="syntax error") as info:
        plugins.load_plugins(["broken.py"], tmp_path)
    assert info.value.line == 1


def test_a_users_plugin_keeps_a_builtin_name_whatever_the_import_order():
    user = type("MyPlanner", (), {"__module__": "my_pkg.planners"})
    builtin = type("NavFn", (), {"__module__": "btnav.planning.navfn"})
    try:
        plugins.register("planner", "btnav/NavFnTest")(user)
        plugins.register("planner", "btnav/NavFnTest")(builtin)  # imported later
        assert plugins.lookup("planner", "btnav/NavFnTest") is user
    finally:
        plugins.unregister("planner", "btnav/NavFnTest")
    plugins.register("planner", "btnav/NavFnTest")(builtin)
    plugins.register("planner", "btnav/NavFnTest")(user)  # a user's replaces a built-in
    assert plugins.lookup("planner", "btnav/NavFnTest") is user
    plugins.unregister("planner", "btnav/NavFnTest")
