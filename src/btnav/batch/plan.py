"""Checking a batch before anything runs, and planning its jobs.

Every mission is loaded (with the `--set` values every run gets), and then once more
for each value of each sweep key, so a misspelt key, a value out of range or a broken
mission stops the batch with the usual located one-line error before a single run
starts, blamed on the `--sweep` option that gave it. Combinations of values are not
each loaded: a run whose combination is refused is an `error` row, not a lost batch.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from os import PathLike
from pathlib import Path
from typing import Any

from ..mission.mission import Mission
from .jobs import BatchError, Job, make_jobs, value_text


def sweep_origins(sweep: Mapping[str, Sequence[Any]]) -> dict[str, str]:
    """`--sweep KEY=V1,V2` as a user would have typed it, for errors about a swept key."""
    return {k: f"--sweep {k}={','.join(value_text(v) for v in vs)}" for k, vs in sweep.items()}


def plan_batch(
    missions: Sequence[str | PathLike[str]],
    *,
    seeds: Sequence[int] | None = None,
    sweep: Mapping[str, Sequence[Any]] | None = None,
    overrides: Mapping[str, Any] | None = None,
    origins: Mapping[str, str] | None = None,
) -> list[Job]:
    """The batch's jobs, after checking every mission and every swept value.

    `origins` maps each override or sweep key to the option that gave it (`--set K=V`,
    `--sweep K=V1,V2`), which an error about it names.
    """
    sweep = dict(sweep or {})
    overrides = dict(overrides or {})
    given = {**sweep_origins(sweep), **(origins or {})}
    if not missions:
        raise BatchError("a batch needs at least one mission")
    for key, values in sweep.items():
        if not values:
            raise BatchError("no value to sweep", file=given.get(key), key=key)
        if key in overrides:
            raise BatchError("both swept and --set", file=given.get(key), key=key)
    loaded: list[tuple[str, str, int]] = []
    names: dict[str, str] = {}
    for path in missions:
        mission = Mission.load(path, overrides=overrides, origins=given)
        if mission.name in names:
            raise BatchError(
                f"two missions are named '{mission.name}' ({names[mission.name]} and "
                f"{mission.file}); their runs would share a folder: rename one (`mission:`)",
                file=str(mission.file),
                key="mission",
            )
        names[mission.name] = str(mission.file)
        with warnings.catch_warnings():  # each mission's warnings were shown by the load above
            warnings.simplefilter("ignore")
            for key, values in sweep.items():
                for value in values:
                    Mission.load(path, overrides={**overrides, key: value}, origins=given)
        loaded.append((str(Path(mission.file).resolve()), mission.name, mission.seed))
    return make_jobs(loaded, seeds, sweep, overrides=overrides, origins=given)
