"""Whole batches: rows, folders, a run that raises, a misspelt key, bytes equal to `btnav run`."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

from btnav.batch import run_batch
from btnav.batch.results import read_rows
from btnav.cli import main
from btnav.plugins import is_registered, unregister

from .short import INFLATION, short_mission

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def six(tmp_path_factory):
    """One batch of 6 runs (3 seeds x 2 inflation radii) on 2 workers, shared by the tests."""
    folder = tmp_path_factory.mktemp("six")
    mission = short_mission(folder)
    out = folder / "out"
    records = run_batch(
        [mission], out=out, seeds=[0, 1, 2], sweep={INFLATION: [0.4, 0.6]}, workers=2
    )
    return mission, out, records


def test_six_runs_on_two_workers_write_six_rows_and_six_folders(six):
    _, out, records = six
    rows = read_rows(out / "results.csv")
    assert len(rows) == 6
    assert sorted((r["seed"], r[INFLATION]) for r in rows) == sorted(
        (str(s), r) for s in range(3) for r in ("0.4", "0.6")
    )
    assert all(r["status"] == "succeeded" and r["collisions"] == "0" for r in rows)
    # the records come back in the batch's order, whatever order the runs ended in
    assert [(r.seed, r.sweep[INFLATION]) for r in records] == [
        (s, v) for v in ("0.4", "0.6") for s in range(3)
    ]
    for r in records:
        folder = out / r.folder
        assert folder == out / "runs" / "short" / f"inflation_radius={r.sweep[INFLATION]}" / (
            f"seed-{r.seed}"
        )
        report = json.loads((folder / "report.json").read_text())
        assert report["seed"] == r.seed and report["sim_time"] == r.sim_time
    assert {"summary.csv", "summary.md"} <= {p.name for p in out.iterdir()}


def test_a_run_alone_and_the_same_run_in_a_batch_write_the_same_bytes(six, tmp_path):
    mission, out, _ = six
    alone = tmp_path / "alone"
    args = ["run", str(mission), "--seed", "1", "--set", f"{INFLATION}=0.6", "--out", str(alone)]
    assert main(args) == 0
    batch = out / "runs" / "short" / "inflation_radius=0.6" / "seed-1"
    assert (alone / "trajectory.csv").read_bytes() == (batch / "trajectory.csv").read_bytes()


def test_running_the_batch_again_runs_nothing_and_returns_the_same_records(six):
    mission, out, records = six
    before = (out / "results.csv").read_bytes()
    again = run_batch([mission], out=out, seeds=[0, 1, 2], sweep={INFLATION: [0.4, 0.6]}, workers=2)
    assert (out / "results.csv").read_bytes() == before
    assert list(again) == list(records)


BOOM = textwrap.dedent(
    """
    from btnav.plugins import register

    @register("output", "boom_on_seed_1")
    class Boom:
        files = ()

        def write(self, run):
            if run.mission.seed == 1:
                raise RuntimeError("boom on seed 1")
    """
)


def test_a_run_that_raises_is_an_error_row_with_its_traceback_and_the_rest_finish(tmp_path, capsys):
    (tmp_path / "boom.py").write_text(BOOM)
    mission = short_mission(
        tmp_path,
        "boomer",
        plugins=[str(tmp_path / "boom.py")],
        outputs=["report", "boom_on_seed_1"],
    )
    out = tmp_path / "out"
    try:
        code = main(["batch", str(mission), "--seeds", "0:3", "--workers", "2", "--out", str(out)])
    finally:
        if is_registered("output", "boom_on_seed_1"):
            unregister("output", "boom_on_seed_1")
    assert code == 1
    rows = {r["seed"]: r for r in read_rows(out / "results.csv")}
    assert sorted(rows) == ["0", "1", "2"]
    assert (
        rows["1"]["status"] == "error" and rows["1"]["error_msg"] == "RuntimeError: boom on seed 1"
    )
    assert rows["0"]["status"] == rows["2"]["status"] == "succeeded"
    trace = (out / rows["1"]["folder"] / "traceback.txt").read_text()
    assert trace.startswith("Traceback") and "boom on seed 1" in trace
    printed = capsys.readouterr().out
    assert "3 runs, 2 succeeded, 1 failed" in printed
    assert "| boomer  | 2/3 67%" in printed


def test_a_misspelt_sweep_key_stops_the_batch_before_any_run(tmp_path, capsys):
    mission = short_mission(tmp_path)
    out = tmp_path / "out"
    bad = "local_costmap.local_costmap.inflation_layer.inflation_radiuss"
    code = main(["batch", str(mission), "--sweep", f"{bad}=0.4,0.6", "--out", str(out)])
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        f"btnav: error: --sweep {bad}=0.4,0.6: {bad}: unknown key 'inflation_radiuss' "
        "(did you mean 'inflation_radius'?)"
    )
    assert not out.exists()


def test_a_misspelt_mission_key_in_a_second_mission_names_its_file_and_line(tmp_path, capsys):
    good = short_mission(tmp_path, "good")
    bad = short_mission(tmp_path, "bad", time_limt=30)
    out = tmp_path / "out"
    assert main(["batch", str(good), str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"btnav: error: {bad}:") and "did you mean 'time_limit'" in err
    assert len(err.splitlines()) == 1 and not out.exists()


def test_the_ray_backend_gives_the_local_backends_records(six, tmp_path):
    pytest.importorskip("ray")
    mission, _, local = six
    records = run_batch(
        [mission],
        out=tmp_path / "ray",
        seeds=[0, 1],
        sweep={INFLATION: [0.6]},
        workers=2,
        backend="ray",
    )

    def same(r):
        return {k: v for k, v in r.row().items() if k != "wall_time"}

    expected = [same(r) for r in local if r.sweep[INFLATION] == "0.6" and r.seed in (0, 1)]
    assert [same(r) for r in records] == expected
    ray_run = tmp_path / "ray" / records[1].folder / "trajectory.csv"
    assert ray_run.read_bytes() == (six[1] / local[4].folder / "trajectory.csv").read_bytes()


def test_the_ray_backend_without_ray_is_one_line(tmp_path, capsys, monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_ray(name, *args, **kwargs):
        if name == "ray" or name.startswith("ray."):
            raise ImportError("No module named 'ray'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_ray)
    mission = short_mission(tmp_path)
    assert main(["batch", str(mission), "--backend", "ray", "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err.strip() == (
        "btnav: error: --backend: the ray backend needs Ray, which is not installed "
        "(pip install 'btnav[ray]')"
    )


def test_a_script_without_a_main_guard_runs_once_however_many_runs_it_starts(tmp_path):
    # multiprocessing runs the parent's main script again in each process it starts by
    # fork server or spawn; a batch's runs need nothing from it, so a script written as
    # a plain list of statements (no `if __name__ == "__main__":`) is not run again
    mission = short_mission(tmp_path)
    script = tmp_path / "sweep.py"
    script.write_text(
        textwrap.dedent(
            f"""
            from btnav.batch import run_batch

            with open({str(tmp_path / "ran.txt")!r}, "a") as log:
                log.write("ran\\n")
            records = run_batch([{str(mission)!r}], out={str(tmp_path / "out")!r},
                                seeds=[0, 1], workers=2)
            print(sorted(r.status for r in records))
            """
        )
    )
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=300, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "['succeeded', 'succeeded']"
    assert (tmp_path / "ran.txt").read_text() == "ran\n"
