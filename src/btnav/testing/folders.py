"""Where a test's runs write: `--btnav-out DIR/<test>/`, kept when the test fails.

Every run a test makes through the plugin (`run_mission`, `btnav_navigator`,
`btnav_tree`) claims a folder here. The first run of a test writes straight into
`DIR/<test nodeid made safe>/`, a second into `run-2/` inside it, and so on. The
plugin deletes the folder after a test that passed; without `--btnav-out` the folders
are temporary and always deleted. Outside a pytest run a claim is a fresh temporary
folder that stays (its path is on what the run returns).

Only the standard library here: the plugin is imported by every pytest session.
"""

from __future__ import annotations

import re
import shutil
import tempfile
from pathlib import Path

#: Longest folder name made from a test id (file systems allow 255 bytes).
MAX_NAME = 120


def safe_name(nodeid: str) -> str:
    """`tests/test_a.py::test_b[x-1]` -> `tests_test_a.py_test_b_x-1`, short enough for a folder."""
    name = re.sub(r"[^\w.-]+", "_", nodeid).strip("_.") or "test"
    if len(name) > MAX_NAME:
        import hashlib

        digest = hashlib.sha1(nodeid.encode()).hexdigest()[:10]
        name = f"{name[: MAX_NAME - 11]}_{digest}"
    return name


class RunFolders:
    """The run folders of one test: claimed as its runs start, kept or deleted at its end."""

    def __init__(self, nodeid: str, out_root: Path | None) -> None:
        self.nodeid = nodeid
        self.out_root = out_root
        self.claimed: list[Path] = []
        self.failed = False
        self._base: Path | None = None

    @property
    def keeps(self) -> bool:
        """Whether a failed test's folders stay (`--btnav-out` given)."""
        return self.out_root is not None

    @property
    def base(self) -> Path | None:
        return self._base

    def claim(self) -> Path:
        """A folder for the next run of this test (created empty)."""
        if self._base is None:
            if self.out_root is None:
                self._base = Path(tempfile.mkdtemp(prefix="btnav-"))
            else:
                self._base = self.out_root / safe_name(self.nodeid)
                if self._base.exists():  # what an earlier session left
                    shutil.rmtree(self._base)
                self._base.mkdir(parents=True)
            folder = self._base
        else:
            folder = self._base / f"run-{len(self.claimed) + 1}"
            folder.mkdir()
        self.claimed.append(folder)
        return folder

    def finish(self) -> None:
        """Delete the folders unless the test failed and `--btnav-out` asked to keep them."""
        if self._base is not None and not (self.failed and self.keeps):
            shutil.rmtree(self._base, ignore_errors=True)

    def section(self) -> str:
        """What the failure report says about the folders."""
        paths = "\n".join(str(p) for p in self.claimed)
        if self.keeps:
            return f"run folder kept (report.json, trajectory.csv, bt_log.jsonl):\n{paths}"
        return (
            f"run folder (deleted after the test):\n{paths}\nrerun with --btnav-out DIR to keep it"
        )


#: The folders of the test now running (set by the plugin's runtest hooks), or None.
_current: RunFolders | None = None


def current() -> RunFolders | None:
    return _current


def set_current(folders: RunFolders | None) -> None:
    global _current
    _current = folders


def claim_folder(label: str = "run") -> tuple[Path, bool]:
    """A folder for a run, and whether the run should also draw `run.png` (kept folders)."""
    folders = _current
    if folders is None:
        return Path(tempfile.mkdtemp(prefix=f"btnav-{safe_name(label)}-")), False
    return folders.claim(), folders.keeps
