"""Odometry sources computed from sensors: laser odometry (rf2o_laser_odometry's role).

The wheel odometry is the simulator's sensor (`btnav.sim.odometry`); this one is built
from scans with Karto's correlative matcher (`btnav.slam.karto`), so it sits beside SLAM
in the layers rather than in `sim`.
"""
