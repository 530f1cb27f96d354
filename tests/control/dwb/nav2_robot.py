"""The robot of Nav2's dwb_plugins tests (twist_gen.cpp's getDefaultKinematicParameters):
0.55 m/s forward, +/-0.1 m/s sideways, 1 rad/s; Nav2's expected numbers assume it."""

from __future__ import annotations

NAV2_TEST_ROBOT = dict(
    min_vel_x=0.0,
    max_vel_x=0.55,
    min_vel_y=-0.1,
    max_vel_y=0.1,
    max_vel_theta=1.0,
    acc_lim_x=2.5,
    acc_lim_y=2.5,
    acc_lim_theta=3.2,
    decel_lim_x=-2.5,
    decel_lim_y=-2.5,
    decel_lim_theta=-3.2,
    min_speed_xy=0.1,
    max_speed_xy=0.55,
    min_speed_theta=0.4,
)
