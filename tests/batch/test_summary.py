"""The summary's numbers on hand-made records, and results.csv's append-safety."""

from __future__ import annotations

import csv
import multiprocessing
import os

import pytest

from btnav.batch import BatchError, RunRecord, summarize, wilson_interval
from btnav.batch.results import ResultsFile, read_rows
from btnav.batch.summary import markdown, write_summary
from btnav.cli.batch_progress import LineProgress


def record(seed: int, status: str = "succeeded", r: str = "0.4", **fields) -> RunRecord:
    values = dict(
        sim_time=10.0 + seed,
        wall_time=1.0,
        path_length=2.0 + seed,
        collisions=0,
        recoveries=seed % 2,
        replans=0,
        missed_waypoints=0,
    )
    values.update(fields)
    if status == "error":
        values = {"error_msg": "RuntimeError: boom"}
    return RunRecord(mission="m", seed=seed, sweep={"a.r": r}, status=status, **values)


def test_wilson_interval_matches_the_textbook_values():
    low, high = wilson_interval(8, 10)
    assert low == pytest.approx(0.4902, abs=1e-4) and high == pytest.approx(0.9433, abs=1e-4)
    assert wilson_interval(10, 10)[1] == 1.0 and wilson_interval(10, 10)[0] == pytest.approx(
        0.7225, abs=1e-4
    )
    assert wilson_interval(0, 10)[0] == 0.0
    assert wilson_interval(0, 0) == (0.0, 1.0)


def test_summary_counts_errors_as_failures_and_times_successes_only():
    runs = [record(s) for s in range(4)]
    runs += [record(4, "failed", sim_time=30.0, collisions=2), record(5, "error")]
    runs += [record(0, r="0.6"), record(1, r="0.6", missed_waypoints=1)]
    first, second = summarize(runs)
    assert (first.runs, first.succeeded, first.errors) == (6, 4, 1)
    assert first.success_rate == pytest.approx(4 / 6)
    assert (first.ci95_low, first.ci95_high) == pytest.approx(wilson_interval(4, 6))
    assert first.sim_time_median == pytest.approx(11.5)  # 10, 11, 12, 13: the failure's 30 is out
    assert first.sim_time_p95 == pytest.approx(12.85)  # numpy's linear interpolation
    assert first.path_length_median == pytest.approx(3.5)
    assert first.collisions_mean == pytest.approx(2 / 5)  # five runs finished, one error
    assert first.recoveries_mean == pytest.approx(2 / 5)
    assert (second.sweep, second.runs, second.succeeded) == ({"a.r": "0.6"}, 2, 1)  # a missed wp
    table = markdown([first, second])
    assert "| m       | 0.4 | 4/6 67% | 30-90% | 11.5 " in table


def test_summary_files(tmp_path):
    written = write_summary(summarize([record(0), record(1, "failed")]), tmp_path)
    assert written[:2] == ["summary.csv", "summary.md"]
    with open(tmp_path / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert rows[0]["a.r"] == "0.4" and rows[0]["runs"] == "2" and rows[0]["succeeded"] == "1"
    pytest.importorskip("matplotlib")
    assert "summary.png" in written and (tmp_path / "summary.png").stat().st_size > 0


def _append_many(path: str, worker: int) -> None:
    results = ResultsFile(path, ["a.r"])  # type: ignore[arg-type]
    for i in range(200):
        results.append({"mission": f"m{worker}", "seed": i, "a.r": "x" * 500, "status": "ok"})


def test_rows_from_several_processes_never_interleave(tmp_path):
    path = tmp_path / "results.csv"
    assert ResultsFile(path, ["a.r"]).open() == []
    ctx = multiprocessing.get_context("fork")
    procs = [ctx.Process(target=_append_many, args=(path, w)) for w in range(4)]
    for p in procs:
        p.start()
    for p in procs:
        p.join()
    rows = read_rows(path)
    assert len(rows) == 800 and all(r["a.r"] == "x" * 500 and r["status"] == "ok" for r in rows)
    assert len({(r["mission"], r["seed"]) for r in rows}) == 800


def test_a_partial_last_line_is_cut_and_other_columns_are_refused(tmp_path):
    path = tmp_path / "results.csv"
    results = ResultsFile(path, ["a.r"])
    results.open()
    results.append(record(0).row())
    with open(path, "ab") as f:
        f.write(b"m,1,0.4,succ")  # a crash mid-row
    assert [r["seed"] for r in ResultsFile(path, ["a.r"]).open()] == ["0"]
    assert path.read_bytes().endswith(b"\n")
    with pytest.raises(BatchError, match="columns of another batch") as err:
        ResultsFile(path, ["b.r"]).open()
    assert str(err.value).startswith(f"{path}: ")
    assert os.path.getsize(path) > 0


def test_a_record_reads_back_equal_from_its_row(tmp_path):
    path = tmp_path / "results.csv"
    results = ResultsFile(path, ["a.r"])
    results.open()
    original = record(3, loc_rms_xy=0.1 + 0.2, error_msg='a, "quoted" message')
    explored = record(4, explored_area=61.75)  # an exploring mission's m² mapped
    results.append(original.row())
    results.append(explored.row())
    rows = read_rows(path)
    assert RunRecord.from_row(rows[0], ["a.r"]) == original
    assert RunRecord.from_row(rows[1], ["a.r"]) == explored
    assert rows[0]["explored_area"] == "" and rows[1]["explored_area"] == "61.75"


def test_the_line_progress_is_one_line_per_run(capsys):
    import sys

    progress = LineProgress(sys.stdout)
    progress.start(3, [record(0)])
    progress.update(record(1, "failed", error_code=105, error_msg="no valid path"))
    progress.update(record(2, "error"))
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "batch: 3 runs, 1 already in results.csv"
    assert lines[1] == "[2/3] m seed=1 r=0.4: failed (error 105: no valid path, 1.0 s wall)"
    assert lines[2].startswith("[3/3] m seed=2 r=0.4: error (RuntimeError: boom; see ")


def test_the_rich_bar_counts_runs_and_failures(monkeypatch):
    pytest.importorskip("rich")
    import io

    import rich.console

    from btnav.cli.batch_progress import RichProgress, default_progress

    assert isinstance(default_progress(io.StringIO()), LineProgress)  # not a terminal
    real = rich.console.Console
    monkeypatch.setattr(
        rich.console, "Console", lambda file: real(file=file, force_terminal=True, width=120)
    )
    out = io.StringIO()
    progress = RichProgress(out)
    progress.start(4, [record(0)])
    progress.update(record(1))
    progress.update(record(2, "failed", error_code=104, error_msg="Failed to make progress"))
    progress.close()
    text = out.getvalue()
    assert "3/4" in text and "67% ok" in text and "1 failed" in text
    assert "m seed=2 r=0.4: failed (error 104: Failed to make progress" in text
