"""The pose graph and its sparse solver, shared by both SLAM engines (Karto's SPA and
Cartographer's global SLAM)."""
