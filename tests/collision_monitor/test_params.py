"""collision_monitor's and collision_detector's sections: Nav2's rules as load errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.core.errors import ParamsError
from btnav.params import load_params
from btnav.params.nav2_known import NAV2_KNOWN_NODES

MONITOR = """\
collision_monitor:
  ros__parameters:
    polygons: ["PolygonStop"]
    PolygonStop:
      type: "polygon"
      points: "{points}"
      action_type: "stop"
    observation_sources: ["scan"]
    scan:
      type: "scan"
      exclusion_zones: ["dock"]
{zone}"""
SQUARE = "[[0.3, 0.3], [0.3, -0.3], [0.0, -0.3], [0.0, 0.3]]"
DOCK = """\
    dock:
      enabled: true
      type: "circle"
      radius: 0.4
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "params.yaml"
    path.write_text(text)
    return path


def test_monitor_section_with_an_exclusion_zone_loads(tmp_path: Path) -> None:
    pf = load_params(write(tmp_path, MONITOR.format(points=SQUARE, zone=DOCK)))
    model = pf.server("collision_monitor").model
    assert model.exclusion_zone_sections["dock"].radius == 0.4
    assert model.source_sections["scan"].exclusion_zones == ["dock"]


def test_three_points_are_too_few_for_nav2(tmp_path: Path) -> None:
    three = "[[0.3, 0.3], [0.3, -0.3], [0.0, -0.3]]"
    with pytest.raises(ParamsError) as info:
        load_params(write(tmp_path, MONITOR.format(points=three, zone=DOCK)))
    assert info.value.key == "collision_monitor.PolygonStop.points" and info.value.line == 6


def test_a_listed_exclusion_zone_needs_its_section(tmp_path: Path) -> None:
    with pytest.raises(ParamsError, match="'dock' is listed but has no section") as info:
        load_params(write(tmp_path, MONITOR.format(points=SQUARE, zone="")))
    assert info.value.key == "collision_monitor.scan.exclusion_zones"


def test_a_stop_polygon_needs_points_or_a_topic(tmp_path: Path) -> None:
    text = MONITOR.format(points="", zone=DOCK)
    with pytest.raises(ParamsError, match="needs points, or polygon_sub_topic"):
        load_params(write(tmp_path, text))
    text = text.replace(
        '      action_type: "stop"', '      action_type: "stop"\n      polygon_sub_topic: "p"'
    )
    assert load_params(write(tmp_path, text)).server("collision_monitor").model


DETECTOR = """\
collision_detector:
  ros__parameters:
    frequency: 5.0
    polygons: ["PolygonFront"]
    PolygonFront:
      type: "polygon"
      points: "[[0.3, 0.3], [0.3, -0.3], [0.0, -0.3], [0.0, 0.3]]"
      action_type: "{action}"
      min_points: 4
    observation_sources: ["scan"]
    scan:
      type: "scan"
"""


def test_collision_detector_is_a_server_btnav_runs(tmp_path: Path) -> None:
    assert "collision_detector" not in NAV2_KNOWN_NODES
    model = (
        load_params(write(tmp_path, DETECTOR.format(action="none")))
        .server("collision_detector")
        .model
    )
    assert model.frequency == 5.0 and list(model.polygon_sections) == ["PolygonFront"]
    with pytest.raises(ParamsError, match='must be "none"') as info:
        load_params(write(tmp_path, DETECTOR.format(action="slowdown")))
    assert info.value.key == "collision_detector.PolygonFront.action_type"
