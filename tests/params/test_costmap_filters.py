"""Nav2's costmap filter sections and zone servers load as btnav runs them."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.cli.params import check_main
from btnav.core.errors import ParamsError
from btnav.core.yaml_io import load_yaml
from btnav.costmap import CostmapROS
from btnav.costmap.filters import KeepoutFilter, SpeedFilter
from btnav.params import load_params
from btnav.params.costmap_filters import CostmapFilterInfoServerParams, FilterMaskServerParams
from btnav.params.loader import load_params_doc
from btnav.params.placeholders import rewrite_launch_tokens


@pytest.fixture(scope="module")
def nav2(nav2_params_file: Path):
    return load_params(nav2_params_file)


def test_params_check_lists_no_filter_as_not_implemented(nav2_params_file, capsys) -> None:
    assert check_main(nav2_params_file) == 0
    out = capsys.readouterr().out
    filters = [line for line in out.splitlines() if "costmap_filter " in line]
    assert len(filters) == 3  # keepout in both costmaps, speed in the global one
    assert not [line for line in filters if "not implemented" in line]
    assert (
        "keepout_filter -> nav2_costmap_2d::KeepoutFilter: "
        "btnav.costmap.filters.keepout_filter.KeepoutFilter" in out
    )
    assert "costmap filters" not in out
    # the zone servers are servers now, not "known but not run"
    for name in ("keepout_filter_mask_server", "speed_costmap_filter_info_server"):
        assert any(line.split() and line.split()[0] == name for line in out.splitlines())


def test_the_zone_servers_sections_are_read(nav2) -> None:
    mask = nav2.server("keepout_filter_mask_server").model
    assert isinstance(mask, FilterMaskServerParams)
    assert (mask.topic_name, mask.yaml_filename, mask.frame_id) == (
        "keepout_filter_mask",
        "",
        "map",
    )
    info = nav2.server("speed_costmap_filter_info_server").model
    assert isinstance(info, CostmapFilterInfoServerParams)
    assert (info.type, info.filter_info_topic, info.mask_topic) == (
        1,
        "speed_costmap_filter_info",
        "speed_filter_mask",
    )
    assert (info.base, info.multiplier) == (100.0, -1.0)


def test_both_costmaps_build_their_filters(nav2) -> None:
    local = CostmapROS.from_params(nav2, "local_costmap")
    glob = CostmapROS.from_params(nav2, "global_costmap")
    assert [type(f) for f in local.filters] == [KeepoutFilter]
    assert [type(f) for f in glob.filters] == [KeepoutFilter, SpeedFilter]
    keepout = glob.filter("keepout_filter")
    assert keepout.params.override_lethal_cost and keepout.params.lethal_override_cost == 200
    # KEEPOUT_ZONE_ENABLED outside a mission: off
    assert not keepout.enabled


def test_launch_tokens_read_false_unless_a_launch_writes_them(nav2, nav2_params_file) -> None:
    shown = {p.key: p.resolved for p in nav2.placeholders}
    assert shown["global_costmap.global_costmap.speed_filter.enabled"].startswith("false")
    doc = load_yaml(nav2_params_file)
    found = rewrite_launch_tokens(doc, {"KEEPOUT_ZONE_ENABLED": True})
    assert {p.key for p in found} == {
        "local_costmap.local_costmap.keepout_filter.enabled",
        "global_costmap.global_costmap.keepout_filter.enabled",
        "global_costmap.global_costmap.speed_filter.enabled",
    }
    params = load_params_doc(doc, nav2_params_file)
    glob = params.server("global_costmap").plugins
    assert glob["keepout_filter"].params.enabled is True
    assert glob["speed_filter"].params.enabled is False


def test_a_filter_without_its_info_topic_is_located(nav2_copy) -> None:
    path, line = nav2_copy(
        'filter_info_topic: "speed_costmap_filter_info"', 'filter_info_topc: "speed"'
    )
    with pytest.raises(ParamsError) as info:
        load_params(path)
    assert (info.value.line, info.value.suggestion) == (line, "filter_info_topic")


def test_an_unknown_filter_type_is_refused(nav2_copy) -> None:
    path, line = nav2_copy("type: 1", "type: 7")
    with pytest.raises(ParamsError) as info:
        load_params(path)
    assert (info.value.line, info.value.key) == (line, "speed_costmap_filter_info_server.type")


def test_a_zone_server_under_a_name_of_its_own_is_known_not_an_error(tmp_path) -> None:
    path = tmp_path / "p.yaml"
    path.write_text("lanes_filter_mask_server:\n  ros__parameters:\n    topic_name: lanes_mask\n")
    params = load_params(path)
    assert "costmap filter server under a name of its own" in params.ignored[0].reason
