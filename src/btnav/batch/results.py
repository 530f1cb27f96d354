"""`results.csv`: one row per finished run, appended the moment the run ends.

Each row goes to the file in one `os.write` on a descriptor opened with `O_APPEND`,
so rows from several writers (two workers, two batches on one folder) never
interleave, and a process killed mid-batch leaves whole rows only. A file that ends
in a partial line (a crash of the machine mid-write) has that tail cut before new
rows are added. The header is written once, by whoever creates the file; a batch
that finds the file already there checks that its columns are the ones it would
write (the same sweep keys), and skips every run whose row is present: that is
resumption.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from .jobs import BatchError

#: The columns before and after the sweep keys' ones.
HEAD = ("mission", "seed")
TAIL = (
    "status",
    "error_code",
    "error_msg",
    "sim_time",
    "wall_time",
    "path_length",
    "collisions",
    "recoveries",
    "replans",
    "missed_waypoints",
    "loc_rms_xy",
    "loc_max_xy",
    "loc_rms_yaw",
    "explored_area",
    "folder",
)
RESULTS_FILE = "results.csv"


def columns(sweep_keys: Sequence[str]) -> list[str]:
    return [*HEAD, *sweep_keys, *TAIL]


def cell(value: Any) -> str:
    """A float with `repr` (the same bits give the same text), None as an empty cell."""
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def format_row(header: Sequence[str], record: Mapping[str, Any]) -> bytes:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([cell(record.get(c)) for c in header])
    return buf.getvalue().encode()


class ResultsFile:
    """The batch's `results.csv`: read what is done, then append rows atomically."""

    def __init__(self, path: Path, sweep_keys: Sequence[str]) -> None:
        self.path = path
        self.header = columns(sweep_keys)
        self.sweep_keys = list(sweep_keys)

    def open(self) -> list[dict[str, str]]:
        """Create the file with its header, or check it and return the rows it has."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        header = format_row(self.header, dict(zip(self.header, self.header, strict=True)))
        try:
            fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            pass
        else:
            try:
                os.write(fd, header)
            finally:
                os.close(fd)
            return []
        self._cut_partial_tail()
        rows = read_rows(self.path)
        found = _header_of(self.path)
        if found != self.header:
            raise BatchError(
                f"it holds the columns of another batch ({', '.join(found or ['none'])}); "
                "give another --out, or the same --sweep keys as before",
                file=str(self.path),
            )
        return rows

    def _cut_partial_tail(self) -> None:
        data = self.path.read_bytes()
        if data and not data.endswith(b"\n"):
            with open(self.path, "r+b") as f:
                f.truncate(data.rfind(b"\n") + 1)

    def append(self, record: Mapping[str, Any]) -> None:
        """One row, in one write on an O_APPEND descriptor: whole or not at all."""
        data = format_row(self.header, record)
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        try:
            written = os.write(fd, data)
            if written != len(data):  # a full disk; never leave a partial row behind
                raise OSError(f"{self.path}: short write ({written} of {len(data)} bytes)")
        finally:
            os.close(fd)


def _header_of(path: Path) -> list[str] | None:
    with open(path, newline="") as f:
        return next(csv.reader(f), None)


def read_rows(path: Path) -> list[dict[str, str]]:
    """The rows of a results.csv (whole lines only), as text."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def row_key(row: Mapping[str, Any], sweep_keys: Sequence[str]) -> tuple[str, ...]:
    """The identity of a row, as `Job.key` spells it."""
    return (str(row["mission"]), str(row["seed"]), *(str(row[k]) for k in sweep_keys))
