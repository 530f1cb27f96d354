"""What a batch runs: the missions x seeds x sweep values, one `Job` per run.

`--seeds` and `--sweep` are read here, so the command line and `run_batch` accept the
same spellings. Seeds are Python's `range` (`0:100` is 100 seeds, `5` one seed, `1,4,7`
a list); a sweep's values are a list (`0.3,0.5`) or a range that includes its stop
(`0.3:0.7:0.1` is five values, as `seq` counts), each value read as YAML as `--set`
reads it. The order of the product is fixed (mission, then sweep values, then seed),
so two invocations of the same batch plan the same jobs in the same order.
"""

from __future__ import annotations

import itertools
import json
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from pathlib import Path
from typing import Any

from ..core.errors import BtnavError, ConfigError
from ..core.yaml_io import load_yaml_text

#: The folder of the runs without a sweep (`runs/<mission>/default/seed-N`).
NO_SWEEP = "default"
#: A range holds at most this many values (a typo such as `0:1:0.0001` is refused).
MAX_RANGE_VALUES = 10_000


class BatchError(ConfigError):
    """A batch's option (`--seeds`, `--sweep`) or results folder that cannot be used."""


@dataclass(frozen=True)
class Job:
    """One run of a batch: a mission file, its seed and the swept values it gets."""

    mission_file: str
    mission: str  # the mission's name (its folder under runs/)
    seed: int
    sweep: tuple[tuple[str, Any], ...] = ()  # (key, value) in the order of --sweep
    overrides: tuple[tuple[str, Any], ...] = ()  # --set values every run gets
    origins: tuple[tuple[str, str], ...] = field(default=(), compare=False)
    #: The directory the batch was started in: a path given by --set/--sweep is relative
    #: to it, and a run on another process (a Ray worker) runs there too.
    cwd: str = field(default_factory=os.getcwd, compare=False)

    @property
    def key(self) -> tuple[str, ...]:
        """What identifies the run in results.csv: mission, seed and each swept value's text."""
        return (self.mission, str(self.seed), *(value_text(v) for _, v in self.sweep))

    @property
    def sweep_label(self) -> str:
        """`inflation_radius=0.4,cost_scaling_factor=3` (the last part of each key)."""
        return sweep_label(self.sweep)

    def folder(self, out: Path) -> Path:
        """`out/runs/<mission>/<sweep>/seed-N`, the run's usual folder."""
        return out / "runs" / _safe(self.mission) / _safe(self.sweep_label) / f"seed-{self.seed}"

    def all_overrides(self) -> dict[str, Any]:
        return {**dict(self.overrides), **dict(self.sweep)}


def value_text(value: Any) -> str:
    """A swept value as results.csv and folder names show it (`0.4`, `true`, `[1, 2]`)."""
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return repr(value)
    return json.dumps(value)


def sweep_label(sweep: Sequence[tuple[str, Any]]) -> str:
    if not sweep:
        return NO_SWEEP
    lasts = [k.split(".")[-1] for k, _ in sweep]
    names = lasts if len(set(lasts)) == len(lasts) else [k for k, _ in sweep]
    return ",".join(f"{n}={value_text(v)}" for n, (_, v) in zip(names, sweep, strict=True))


def _safe(text: str) -> str:
    """A folder name: path separators and odd characters become `_`."""
    return re.sub(r"[^A-Za-z0-9._=,+-]", "_", text) or "_"


def parse_seeds(text: str, *, origin: str | None = None) -> list[int]:
    """The seeds of a `--seeds` option, in order, without repeats.

    Args:
        text: `0:10` (0..9, as Python's range), `5`, `1,4,7` or `0:100:10`.
        origin: where the text came from, for the error (default `--seeds TEXT`).

    Returns:
        The seeds; a malformed or empty text raises `BatchError`.
    """
    where = origin or f"--seeds {text}"
    try:
        if ":" in text:
            parts = [int(p) for p in text.split(":")]
            if len(parts) not in (2, 3) or (len(parts) == 3 and parts[2] <= 0):
                raise ValueError
            seeds = list(range(*parts))
        else:
            seeds = [int(p) for p in text.split(",")]
    except ValueError:
        raise BatchError(
            "seeds are START:STOP (STOP excluded, as Python's range), START:STOP:STEP, "
            f"N or N1,N2,...; got '{text}'",
            file=where,
        ) from None
    if not seeds:
        raise BatchError(f"'{text}' holds no seed (STOP is excluded)", file=where)
    return list(dict.fromkeys(seeds))


def _decimal(text: str) -> Decimal | None:
    try:
        value = Decimal(text.strip())
    except InvalidOperation:
        return None
    return value if value.is_finite() else None


def parse_values(text: str, *, origin: str) -> list[Any]:
    """The values of one swept key.

    Args:
        text: `0.3,0.5` (each read as YAML) or `0.3:0.7:0.1` (a range, stop included,
            counted in exact decimals so 0.1 steps land on 0.3, 0.4, ...).
        origin: the option as typed, for the error.

    Returns:
        The values, ints when every part of a range is integral.
    """
    parts = text.split(":")
    if len(parts) == 3 and all(_decimal(p) is not None for p in parts):
        start, stop, step = (_decimal(p) for p in parts)
        assert start is not None and stop is not None and step is not None
        if step == 0 or (stop - start) / step < 0:
            raise BatchError(
                f"the range '{text}' is empty (START:STOP:STEP, STOP included)", file=origin
            )
        count = int((stop - start) / step) + 1
        if count > MAX_RANGE_VALUES:
            raise BatchError(f"the range '{text}' holds {count} values", file=origin)
        integral = all("." not in p and "e" not in p.lower() for p in parts)
        values = [start + i * step for i in range(count)]  # exact decimals: 0.3, 0.4, ...
        return [int(v) if integral else float(v) for v in values]
    values = []
    for item in text.split(","):
        if not item.strip():
            raise BatchError(f"an empty value in '{text}'", file=origin)
        try:
            values.append(load_yaml_text(item))
        except BtnavError as err:
            raise BatchError(
                f"cannot read the value '{item}': {err.message}", file=origin
            ) from None
    return values


def parse_sweep(texts: Sequence[str]) -> tuple[dict[str, list[Any]], dict[str, str]]:
    """The `--sweep KEY=V1,V2` options of a command line.

    Args:
        texts: each option's text, `KEY=V1,V2,...` or `KEY=START:STOP:STEP`.

    Returns:
        The values by key (repeats dropped) and each key's option as typed (for errors).
    """
    sweep: dict[str, list[Any]] = {}
    origins: dict[str, str] = {}
    for text in texts:
        origin = f"--sweep {text}"
        key, sep, values = text.partition("=")
        key = key.strip()
        if not sep or not key or not values.strip():
            raise BatchError(f"expected KEY=V1,V2,... or KEY=START:STOP:STEP, got '{text}'")
        if key in sweep:
            raise BatchError(f"'{key}' is swept twice", file=origin, key=key)
        if key in ("mission.seed", "seed"):
            raise BatchError("sweep seeds with --seeds", file=origin, key=key)
        values_list = parse_values(values, origin=origin)
        sweep[key] = list(dict.fromkeys(values_list)) if _hashable(values_list) else values_list
        origins[key] = origin
    return sweep, origins


def _hashable(values: list[Any]) -> bool:
    return all(isinstance(v, str | int | float | bool) or v is None for v in values)


def make_jobs(
    missions: Sequence[tuple[str, str, int]],
    seeds: Sequence[int] | None,
    sweep: Mapping[str, Sequence[Any]],
    *,
    overrides: Mapping[str, Any] | None = None,
    origins: Mapping[str, str] | None = None,
) -> list[Job]:
    """Every (mission, sweep values, seed); `missions` are (file, name, its own seed), whose
    seed is used when `seeds` is None."""
    keys = list(sweep)
    combos = list(itertools.product(*(sweep[k] for k in keys)))
    fixed = tuple((overrides or {}).items())
    given = tuple((origins or {}).items())
    jobs = []
    for file, name, own_seed in missions:
        for combo in combos:
            for seed in seeds if seeds is not None else [own_seed]:
                jobs.append(
                    Job(
                        mission_file=file,
                        mission=name,
                        seed=seed,
                        sweep=tuple(zip(keys, combo, strict=True)),
                        overrides=fixed,
                        origins=given,
                    )
                )
    return jobs
