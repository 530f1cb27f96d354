"""slam_toolbox's engine: Karto's graph SLAM (its `lib/karto_sdk`) and the node around it.

`slam_toolbox.SlamToolbox` is the `slam_toolbox` plugin (`localization: slam`); the
mapper, scan matcher and correlation grid are Karto's; the scan gate, odometry fusion,
continued mapping, graph localiser and graph files are slam_toolbox's own. Cartographer,
the other engine, is `btnav.slam.cartographer`; both optimise `btnav.slam.graph`.
"""
