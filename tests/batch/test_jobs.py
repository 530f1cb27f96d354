"""Reading --seeds and --sweep, and the product of jobs: what a user types, what runs."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.batch import BatchError, parse_seeds, parse_sweep, parse_values
from btnav.batch.jobs import make_jobs


def test_a_range_includes_its_stop_and_gives_exact_decimals():
    assert parse_values("0.3:0.7:0.1", origin="x") == [0.3, 0.4, 0.5, 0.6, 0.7]
    assert parse_values("1:9:4", origin="x") == [1, 5, 9]
    assert all(type(v) is int for v in parse_values("1:9:4", origin="x"))
    assert parse_values("0.5:0.2:-0.1", origin="x") == [0.5, 0.4, 0.3, 0.2]


def test_a_list_is_read_as_yaml_values():
    assert parse_values("0.3,1,true,abc", origin="x") == [0.3, 1, True, "abc"]


@pytest.mark.parametrize("text", ["0.3:0.7:0", "0.7:0.3:0.1"])
def test_an_empty_range_is_refused(text):
    with pytest.raises(BatchError, match="empty"):
        parse_values(text, origin=f"--sweep k={text}")


def test_seeds_are_pythons_range_or_a_list():
    assert parse_seeds("0:4") == [0, 1, 2, 3]
    assert parse_seeds("0:10:5") == [0, 5]
    assert parse_seeds("7") == [7]
    assert parse_seeds("3,1,3") == [3, 1]
    with pytest.raises(BatchError, match="START:STOP") as err:
        parse_seeds("a:b")
    assert str(err.value).startswith("--seeds a:b: ")


def test_sweep_options_keep_their_order_and_refuse_seed_and_repeats():
    sweep, origins = parse_sweep(["a.b=0.3:0.5:0.1", "mission.time_limit=10,20"])
    assert sweep == {"a.b": [0.3, 0.4, 0.5], "mission.time_limit": [10, 20]}
    assert origins["a.b"] == "--sweep a.b=0.3:0.5:0.1"
    with pytest.raises(BatchError, match="--seeds"):
        parse_sweep(["mission.seed=1,2"])
    with pytest.raises(BatchError, match="twice"):
        parse_sweep(["a.b=1", "a.b=2"])
    with pytest.raises(BatchError, match="KEY=V1,V2"):
        parse_sweep(["a.b"])


def test_the_product_is_missions_then_values_then_seeds():
    jobs = make_jobs([("m.yaml", "m", 5)], [0, 1], {"x.radius": [0.4, 0.6], "y.n": [1]})
    assert [(j.seed, dict(j.sweep)) for j in jobs] == [
        (0, {"x.radius": 0.4, "y.n": 1}),
        (1, {"x.radius": 0.4, "y.n": 1}),
        (0, {"x.radius": 0.6, "y.n": 1}),
        (1, {"x.radius": 0.6, "y.n": 1}),
    ]
    assert jobs[2].folder(Path("out")) == Path("out/runs/m/radius=0.6,n=1/seed-0")
    assert jobs[2].key == ("m", "0", "0.6", "1")
    own = make_jobs([("m.yaml", "m", 5)], None, {})
    assert [(j.seed, j.folder(Path("o"))) for j in own] == [(5, Path("o/runs/m/default/seed-5"))]
