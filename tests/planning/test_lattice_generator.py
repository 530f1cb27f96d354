"""The lattice generator: control sets judged by geometry, Nav2's own sets, the shipped files."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from btnav.core.errors import BtnavError
from btnav.planning.lattice_generator import (
    LatticeConfig,
    generate_lattice,
    lattice_document,
    main,
    read_config,
)
from btnav.planning.smac_planner_lattice import load_lattice

REPO = Path(__file__).resolve().parents[2]
SHIPPED = REPO / "params" / "lattice"
NAV2_MIRROR = Path("/work/.mirror/ros-navigation+navigation2/repo")
NAV2_SAMPLES = "nav2_smac_planner/lattice_primitives/sample_primitives"


def turns(prim_poses: np.ndarray, start_yaw: float) -> tuple[np.ndarray, np.ndarray]:
    """Heading change and distance between consecutive poses, from the start (0, 0)."""
    poses = np.vstack([[0.0, 0.0, start_yaw], prim_poses])
    ds = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    dyaw = np.abs(np.remainder(np.diff(poses[:, 2]) + np.pi, 2 * np.pi) - np.pi)
    return dyaw, ds


def test_racecar_lattice_never_turns_tighter_than_its_radius_and_ends_on_lattice_points():
    lattice = load_lattice(SHIPPED / "racecar_ackermann_1.4m_5cm.json")
    r, res = 1.4, 0.05
    assert (lattice.motion_model, lattice.turning_radius, lattice.num_of_headings) == (
        "ackermann",
        r,
        16,
    )
    angles = np.array(lattice.heading_angles)
    assert sorted({p.start_angle_index for p in lattice.primitives}) == list(range(16))
    for prim in lattice.primitives:
        assert prim.trajectory_radius == 0.0 or prim.trajectory_radius >= r
        dyaw, ds = turns(prim.poses, angles[prim.start_angle_index])
        assert np.all(ds > 0.0)  # an Ackermann base never turns on the spot
        # the chord of an arc is shorter than the arc: 1 % slack on 5 cm steps
        assert np.max(dyaw / ds) <= 1.0 / r * 1.01
        end = prim.poses[-1]
        cells = end[:2] / res
        assert np.allclose(cells, np.round(cells), atol=1e-6), prim.trajectory_id
        gap = math.remainder(end[2] - angles[prim.end_angle_index], 2 * math.pi)
        assert abs(gap) < 1e-9
        length = np.sum(ds)
        assert prim.trajectory_length == pytest.approx(length, abs=2e-3)
        assert prim.trajectory_length == pytest.approx(
            prim.arc_length + prim.straight_length, abs=2e-5
        )


def test_the_shipped_files_are_what_their_configs_generate():
    for config_file in sorted((SHIPPED / "config").glob("*.json")):
        config = read_config(config_file)
        doc = lattice_document(config, generate_lattice(config))
        shipped = json.loads((SHIPPED / config_file.name).read_text())
        doc["date_generated"] = shipped["date_generated"]
        assert json.loads(json.dumps(doc)) == shipped, config_file.name


def test_headings_point_at_lattice_points_so_straights_end_on_them():
    config = LatticeConfig(
        motion_model="ackermann", turning_radius=0.5, grid_resolution=0.05,
        stopping_threshold=5, num_of_headings=16, trajectory_distinctness_ratio=0.9,
    )  # fmt: skip
    doc = lattice_document(config, generate_lattice(config))
    angles = doc["lattice_metadata"]["heading_angles"]
    assert angles[:5] == pytest.approx(
        [0.0, math.atan(0.5), math.pi / 4, math.atan(2), math.pi / 2]
    )
    assert all(0.0 <= a < 2 * math.pi for a in angles)
    straights = [p for p in doc["primitives"] if p["trajectory_radius"] == 0.0]
    assert {p["start_angle_index"] for p in straights} == set(range(16))  # one per heading
    for p in straights:
        assert p["start_angle_index"] == p["end_angle_index"]
        assert p["arc_length"] == 0.0 and p["straight_length"] == p["trajectory_length"]


def test_diff_adds_rotations_in_place_and_omni_slides_sideways_both_ways_alike():
    base = dict(turning_radius=0.5, grid_resolution=0.05, stopping_threshold=5,
                num_of_headings=16, trajectory_distinctness_ratio=0.9)  # fmt: skip
    ackermann = generate_lattice(LatticeConfig(motion_model="ackermann", **base))
    diff = generate_lattice(LatticeConfig(motion_model="diff", **base))
    omni = generate_lattice(LatticeConfig(motion_model="omni", **base))
    assert len(diff) == len(ackermann) + 2 * 16 and len(omni) == len(diff) + 2 * 16
    rotations = [p for p in diff if p.length == 0.0]
    assert sorted((p.start_index, p.end_index) for p in rotations) == sorted(
        [(k, (k + 1) % 16) for k in range(16)] + [(k, (k - 1) % 16) for k in range(16)]
    )
    for p in rotations:
        assert np.all(p.poses[:, :2] == 0.0)
    slides = [p for p in omni if p.start_index == p.end_index and p.length > 0.0]
    for k in range(16):
        mine = [p for p in slides if p.start_index == k]
        assert len(mine) == 3  # ahead, to the left, to the right
        lengths = sorted(p.length for p in mine)
        assert lengths[0] == pytest.approx(lengths[2])  # Nav2's files make the right one 3x
        for p in mine:
            assert np.all(p.poses[:, 2] == p.poses[0, 2])  # the base keeps its heading


@pytest.mark.skipif(not NAV2_MIRROR.is_dir(), reason="Nav2's repository is not mirrored here")
@pytest.mark.parametrize(
    "sample",
    [
        "5cm_resolution/0.5m_turning_radius/ackermann/output.json",
        "5cm_resolution/1m_turning_radius/diff/output.json",
        "5cm_resolution/0.5m_turning_radius/omni/output.json",
        "old_5cm_resolution/0.5m_turning_radius/ackermann/output.json",
    ],
)
def test_nav2s_sample_sets_come_out_the_same(sample):
    show = subprocess.run(
        ["git", "-C", str(NAV2_MIRROR), "show", f"HEAD:{NAV2_SAMPLES}/{sample}"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    nav2 = json.loads(show.stdout)
    meta = nav2["lattice_metadata"]
    keys = (
        "motion_model",
        "turning_radius",
        "grid_resolution",
        "stopping_threshold",
        "num_of_headings",
    )
    config = LatticeConfig(
        **{k: meta[k] for k in keys},
        trajectory_distinctness_ratio=meta.get("trajectory_distinctness_ratio", 0.0),
    )
    mine = lattice_document(config, generate_lattice(config))

    def ends(doc):
        return [
            (p["start_angle_index"], p["end_angle_index"], *np.round(p["poses"][-1][:2], 4))
            for p in doc["primitives"]
        ]

    assert ends(mine) == ends(nav2)
    for a, b in zip(mine["primitives"], nav2["primitives"], strict=True):
        # Nav2 rounds its construction to 5 decimals on the way; btnav rounds the result
        assert a["trajectory_radius"] == pytest.approx(b["trajectory_radius"], abs=2e-5)
        assert a["arc_length"] == pytest.approx(b["arc_length"], abs=2e-5)
    assert mine["lattice_metadata"]["heading_angles"] == pytest.approx(meta["heading_angles"])


def test_a_config_mistake_names_its_file_and_line(tmp_path):
    config = tmp_path / "config.json"
    config.write_text(
        '{\n  "motion_model": "ackermann",\n  "turning_radius": 0.5,\n'
        '  "grid_resolution": 0.05,\n  "stoping_threshold": 5,\n  "num_of_headings": 16\n}\n'
    )
    with pytest.raises(BtnavError) as err:
        read_config(config)
    assert err.value.file == str(config) and err.value.line == 5
    assert err.value.suggestion == "stopping_threshold"
    config.write_text(config.read_text().replace("stoping", "stopping").replace("16", "12"))
    with pytest.raises(BtnavError, match="multiple of 8") as err:
        read_config(config)
    assert err.value.line == 6


def test_the_command_writes_a_file_the_planner_loads(tmp_path, capsys):
    config = tmp_path / "config.json"
    config.write_text(json.dumps({
        "motion_model": "diff", "turning_radius": 0.4, "grid_resolution": 0.1,
        "stopping_threshold": 5, "num_of_headings": 8, "trajectory_distinctness_ratio": 0.9,
    }))  # fmt: skip
    out = tmp_path / "out.json"
    assert main(["--config", str(config), "--output", str(out)]) == 0
    lattice = load_lattice(out)
    assert lattice.num_of_headings == 8 and lattice.grid_resolution == 0.1
    assert "primitives" in capsys.readouterr().out
    (tmp_path / "bad.json").write_text('{"motion_model": "car"}')
    assert main(["--config", str(tmp_path / "bad.json"), "--output", str(out)]) == 2
    assert "btnav: error:" in capsys.readouterr().err
