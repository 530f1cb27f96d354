"""Cartographer's 2D SLAM (`localization: cartographer`), driven by the user's `.lua`.

Laid out as Cartographer's `mapping/internal/2d`: the options and their Lua sandbox
(`config`, `options`, `lua_sandbox`, Cartographer's own defaults in `defaults/`),
submaps, the scan matchers (`matchers`, `fast_correlative_matcher`), local and global
SLAM with the plugin (`slam`) and the offline run. slam_toolbox's Karto, the other
engine, is `btnav.slam.karto`; both optimise `btnav.slam.graph`.
"""
