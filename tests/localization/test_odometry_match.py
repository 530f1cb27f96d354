"""AMCL's alphas against a world's odometry noise: the conversion, the shipped matched
params file, and the note a mission gets when the two differ by more than 10x."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.cli import main
from btnav.localization.amcl import DifferentialMotionModel
from btnav.localization.amcl.odometry_match import (
    MARGIN,
    alpha_mismatch_note,
    matched_alphas,
    world_noise_alphas,
)
from btnav.params import load_params
from btnav.sim.odometry_noise import sample_motion

REPO = Path(__file__).resolve().parents[2]
NAV2 = REPO / "params" / "nav2_params.yaml"
MATCHED = REPO / "params" / "nav2_params_matched_amcl.yaml"
BUNDLED = (0.002, 0.0005, 0.0001, 0.0001)  # small_office, warehouse, four_rooms...
AISLE = (0.005, 0.001, 0.005, 0.001)  # worlds/aisle_warehouse.yaml (issue 34's robot)
GATES = (0.25, 0.2)  # Nav2's update_min_d, update_min_a


def world_drift(alphas, motion, n=200_000, steps=50, seed=0):
    """(heading std, along-track std) of btnav's simulated wheel odometry after `motion`
    (dx, dyaw in the robot frame) driven in `steps` odometry updates."""
    rng = np.random.default_rng(seed)
    step = (motion[0] / steps, 0.0, motion[1] / steps)
    poses = np.zeros((n, 3))
    for _ in range(steps):
        poses = sample_motion(poses, step, alphas, rng)
    return poses[:, 2].std(), poses[:, 0].std()


def test_converted_alphas_give_amcl_the_worlds_drift_over_one_update_at_the_gates():
    ref = world_noise_alphas(AISLE, *GATES)
    assert ref == pytest.approx((0.025, 0.004, 0.02, 0.005))
    model = DifferentialMotionModel(*ref)
    # driving update_min_d straight: AMCL's heading and along-track spread = the world's
    *_, s1, st, s2 = model.stds((0.25, 0.0, 0.0), (0.25, 0.0, 0.0))
    heading, along = world_drift(AISLE, (0.25, 0.0))
    assert math.hypot(s1, s2) == pytest.approx(heading, rel=0.08)
    assert st == pytest.approx(along, rel=0.08)
    # turning update_min_a in place: the heading spread too
    *_, s1, st, s2 = model.stds((0.0, 0.0, 0.2), (0.0, 0.0, 0.2))
    heading, _ = world_drift(AISLE, (0.0, 0.2))
    assert math.hypot(s1, s2) == pytest.approx(heading, rel=0.08)
    # the same numbers used as alphas give a quarter of that variance: half the spread
    *_, s1, st, s2 = DifferentialMotionModel(*AISLE).stds((0.25, 0.0, 0.0), (0.25, 0.0, 0.0))
    assert st == pytest.approx(0.5 * along, rel=0.08)
    assert matched_alphas(AISLE, *GATES) == pytest.approx(tuple(MARGIN * a for a in ref))


def test_the_shipped_matched_file_is_nav2s_with_alphas_matched_and_the_prob_laser_model():
    nav2, matched = yaml.safe_load(NAV2.read_text()), yaml.safe_load(MATCHED.read_text())
    a_nav2, a_matched = nav2["amcl"]["ros__parameters"], matched["amcl"]["ros__parameters"]
    keys = ("alpha1", "alpha2", "alpha3", "alpha4", "laser_model_type")
    assert [a_matched[k] for k in keys[:4]] == pytest.approx(matched_alphas(BUNDLED, *GATES))
    assert a_matched["laser_model_type"] == "likelihood_field_prob"
    assert {k: v for k, v in a_matched.items() if k not in keys} == {
        k: v for k, v in a_nav2.items() if k not in keys
    }
    assert {k: v for k, v in matched.items() if k != "amcl"} == {
        k: v for k, v in nav2.items() if k != "amcl"
    }
    load_params(MATCHED)  # and it loads as any params file


def test_the_note_names_how_far_apart_the_alphas_are_and_the_values_to_use():
    note = alpha_mismatch_note(AISLE, [0.2] * 5, *GATES)
    assert note is not None and "\n" not in note
    assert "8-50x" in note  # Nav2's 0.2 against [0.025, 0.004, 0.02, 0.005]
    assert "[0.25, 0.04, 0.2, 0.05]" in note  # what to use
    bundled = alpha_mismatch_note(BUNDLED, [0.2] * 5, *GATES)
    assert bundled is not None and "20-500x" in bundled and "[0.1, 0.02, 0.004, 0.005]" in bundled
    # alphas set to the world's numbers trust the odometry 4-5x too much: noted too
    under = alpha_mismatch_note(AISLE, AISLE, *GATES)
    assert under is not None and "as little as 0.2x" in under


def test_no_note_when_they_agree_for_laser_odometry_or_exact_wheels():
    assert alpha_mismatch_note(BUNDLED, matched_alphas(BUNDLED, *GATES), *GATES) is None
    assert alpha_mismatch_note(AISLE, matched_alphas(AISLE, *GATES), *GATES) is None
    assert alpha_mismatch_note(AISLE, [0.2] * 5, *GATES, source="laser") is None
    assert alpha_mismatch_note((0.0, 0.0, 0.0, 0.0), [0.2] * 5, *GATES) is None
    # the bundled robot's file on issue 34's robot: its alpha3 is 5x too small
    note = alpha_mismatch_note(AISLE, matched_alphas(BUNDLED, *GATES), *GATES)
    assert note is not None and "as little as 0.2x" in note


def test_btnav_run_prints_one_note_line_at_the_amcl_section(tmp_path, capsys):
    mission = REPO / "missions" / "aisle_warehouse_tour.yaml"
    main(["run", str(mission), "--set", "mission.time_limit=1", "-o", str(tmp_path)])
    notes = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("btnav: note:")]
    assert len(notes) == 1
    assert "nav2_params.yaml:" in notes[0] and "amcl: alpha1-4 [0.2, 0.2, 0.2, 0.2]" in notes[0]
