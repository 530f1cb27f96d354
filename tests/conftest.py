"""Shared test fixtures: where Nav2's own files live; what numba compiled."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED_NAV2 = REPO.parent / "shared" / "nav2"

pytest_plugins = ["pytester"]  # tests/testing runs a user's project with it


@pytest.fixture(scope="session")
def nav2_dir() -> Path:
    if not SHARED_NAV2.is_dir():
        pytest.fail(f"Nav2's corpus is missing: expected {SHARED_NAV2} beside the repo")
    return SHARED_NAV2


@pytest.fixture(scope="session")
def nav2_params_file(nav2_dir: Path) -> Path:
    return nav2_dir / "params" / "nav2_params.yaml"


#: x86-64's fused multiply-add instructions (vfmadd231sd, vfnmsub132ps, ...).
FUSED_MULTIPLY_ADD = r"\bv?f(?:n?m(?:add|sub))\w*"

_COUNT_FUSED = """
import re
text = "".join(a for f in ({kernels}) for a in f.inspect_asm().values())
print(len(text), len(re.findall({pattern!r}, text)))
"""


@pytest.fixture
def fused_multiply_adds(tmp_path: Path) -> Callable[[str, str], tuple[int, int]]:
    """`count(setup, kernels) -> (characters of assembly, fused multiply-adds in it)`:
    `setup` compiles the kernels in a fresh interpreter with an empty numba cache (only a
    fresh compile can show its assembly); `kernels` is the tuple of them, as code."""

    def count(setup: str, kernels: str) -> tuple[int, int]:
        code = setup + _COUNT_FUSED.format(kernels=kernels, pattern=FUSED_MULTIPLY_ADD)
        env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
        done = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True,
            check=True, cwd=REPO,
        )  # fmt: skip
        n_chars, n_fused = (int(v) for v in done.stdout.split())
        return n_chars, n_fused

    return count


_SHORT_RUN = """
import hashlib, sys
from pathlib import Path
sys.path.insert(0, {missions!r})
from missions import write_mission
from btnav.mission import Mission, run_mission
out = Path({out!r})
path = write_mission(
    out, "short", localization="amcl", task={{"navigate_to_pose": [3.0, 2.0, 1.57]}}
)
run_mission(Mission.load(path), out / "run")
print(hashlib.sha256((out / "run" / "trajectory.csv").read_bytes()).hexdigest())
"""


def short_run_digest(out: Path, **env: str) -> str:
    """sha256 of trajectory.csv of a short AMCL run (seed 0), in a fresh interpreter with
    `env` added: the run the pinned digest and the kernels' same-bits tests compare."""
    out.mkdir(parents=True, exist_ok=True)
    code = _SHORT_RUN.format(missions=str(Path(__file__).parent / "mission"), out=str(out))
    done = subprocess.run(
        [sys.executable, "-c", code],
        env={**os.environ, **env},
        capture_output=True,
        text=True,
        check=True,
    )
    return done.stdout.split()[-1]


@pytest.fixture(name="short_run_digest", scope="session")
def _short_run_digest() -> Callable[..., str]:
    return short_run_digest
