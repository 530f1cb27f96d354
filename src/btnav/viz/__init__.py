"""Pictures of what btnav simulates and computes (PNG/GIF); needs the `viz` extra (matplotlib).

Modules here import matplotlib lazily, only when they draw, so `import btnav.viz...`
works without it and a missing matplotlib is a clear `BtnavError`, not an ImportError.
"""
