"""Packs the repo's bundled folders into the wheel as `btnav/data/<kind>`.

`core.resources.bundled_dir` finds them there in an installed btnav, and in the
checkout itself for an editable install; everything else is in pyproject.toml.
"""

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent
BUNDLED = ("trees", "worlds", "maps", "params", "missions", "robots", "graphs")


class BuildPyWithData(build_py):
    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            return
        for kind in BUNDLED:
            src = ROOT / kind
            if src.is_dir():
                dest = Path(self.build_lib) / "btnav" / "data" / kind
                shutil.copytree(src, dest, dirs_exist_ok=True)


setup(cmdclass={"build_py": BuildPyWithData})
