"""Mask values -> costs and filter values, as Nav2's costmap filters compute them."""

from __future__ import annotations

import numpy as np

from btnav.costmap import LETHAL_OBSTACLE, NO_INFORMATION
from btnav.costmap.filters import SPEED_FILTER_PERCENT, CostmapFilterInfo, mask_cost


def test_mask_values_scale_onto_costs_rounding_half_away_from_zero() -> None:
    costs = mask_cost([-1, 0, 25, 50, 75, 99, 100])
    # 25 * 2.54 = 63.5 -> 64 and 75 * 2.54 = 190.5 -> 191 (std::round), not banker's 190
    assert costs.tolist() == [NO_INFORMATION, 0, 64, 127, 191, 251, LETHAL_OBSTACLE]


def test_filter_value_is_base_plus_multiplier_times_mask_value() -> None:
    # Nav2's speed zone: base 100, multiplier -1 -> a mask value of 25 is 75 % of full speed
    info = CostmapFilterInfo(SPEED_FILTER_PERCENT, "speed_filter_mask", 100.0, -1.0)
    assert info.filter_value(np.array([20, 25, 50])).tolist() == [80.0, 75.0, 50.0]


def test_base_and_multiplier_arrive_as_float32() -> None:
    # The message carries float32: 0.01 m/s per mask unit is what a filter computes with.
    info = CostmapFilterInfo(2, "mask", 0.0, 0.01)
    assert info.multiplier == float(np.float32(0.01)) != 0.01
    assert float(info.filter_value(50)) == 50 * float(np.float32(0.01))
