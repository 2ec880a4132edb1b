"""Run directories as propeller-analysis input: what each run stands for (transit distance, speed, fraction
reaching, propellers) and the check that pooled runs describe the same conditions. Pure: the files are read
by `floebreak.output.run_files`, and `floebreak.app.propeller.read_runs` combines the two.

Transit distance of a run (documented rule, docs/propeller.md §6): the length along x of the overlap of the
stem's travel [x_start_m, x_start_m + (n_steps − 1) step_m] (``pieces.parquet`` metadata) with the field's
x-extent (``field.parquet`` metadata ``domain_m``): the ice the ship sailed through. With the default end
(the hull passes the whole field) it is the field length ahead of the start.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import pyarrow as pa

from floebreak.errors import InputError
from floebreak.propeller.rates import RateBasis, RunExposure

POOLABLE_KEYS = ("seed", "field", "name")  # runs may differ in these and still be pooled without --pool


@dataclass(frozen=True)
class RunInputs:
    """Cusps of one or more run directories, a RunExposure per run (None when a run lacks the files
    needed for its transit distance), the scenario keys that differ between the runs and the runs'
    scenario `profile` ("default" unless every run's resolved scenario says "thesis")."""

    cusps: pa.Table
    exposures: dict[str, RunExposure] | None
    run_dirs: dict[str, Path]
    differing_keys: tuple[str, ...]
    missing_transit: tuple[str, ...]
    profile: str = "default"


def transit_distance_m(field: dict, pieces: dict) -> float | None:
    """The run's transit distance in ice [m] (module docstring) from the metadata of its ``field.parquet``
    and ``pieces.parquet``; None without the keys."""
    try:
        x_min, _, x_max, _ = (float(v) for v in field["domain_m"])
        x_start, step, n_steps = float(pieces["x_start_m"]), float(pieces["step_m"]), int(pieces["n_steps"])
    except (KeyError, TypeError, ValueError):
        return None
    x_last = x_start + (n_steps - 1) * step
    distance = min(x_max, x_last) - max(x_min, x_start)
    return distance if distance > 0.0 else None


def _differing(scenarios: dict[str, dict | None]) -> tuple[str, ...]:
    """Top-level scenario keys (dotted one level down) in which the runs differ, ignoring POOLABLE_KEYS;
    ("scenario.resolved.toml",) when a run has none and there are several runs."""
    if len(scenarios) < 2:
        return ()
    if any(s is None for s in scenarios.values()):
        return ("scenario.resolved.toml",)
    keys: set[str] = set()
    items = list(scenarios.values())
    for section in {k for s in items for k in s} - set(POOLABLE_KEYS):
        values = [s.get(section) for s in items]
        if isinstance(values[0], dict):
            for key in {k for v in values for k in (v or {})}:
                if len({json.dumps((v or {}).get(key), sort_keys=True) for v in values}) > 1:
                    keys.add(f"{section}.{key}")
        elif len({json.dumps(v, sort_keys=True) for v in values}) > 1:
            keys.add(section)
    return tuple(sorted(keys))


def _basis(scenario: dict | None, overrides: dict, source: str = "") -> RateBasis:
    ship = (scenario or {}).get("ship", {})
    prop = (scenario or {}).get("propeller", {})
    values = {
        "speed_m_s": ship.get("speed_m_s"),
        "fraction_reaching": prop.get("fraction_reaching"),
        "n_propellers": prop.get("count"),
    }
    given = {k: v for k, v in overrides.items() if v is not None}
    RateBasis(**given)  # the overrides alone first: their error names no file
    given = {**{k: v for k, v in values.items() if v is not None}, **given}
    try:
        return RateBasis(**given)
    except InputError as error:  # a value from the scenario file: name the file
        raise InputError(
            error.field, f"{source}: {str(error).partition(': ')[2]}", value=error.value
        ) from None


def run_inputs(
    root: Path,
    cusps: pa.Table,
    runs: dict[str, tuple[Path, dict | None, float | None]],
    *,
    pool: bool = False,
    **basis_overrides,
) -> RunInputs:
    """`RunInputs` of the runs below `root`: `runs` maps run_id → (run directory, resolved scenario or None,
    transit distance or None). Several runs are pooled only if their resolved scenarios differ in nothing
    but seed, field and name, or with `pool=True`; otherwise InputError naming the differing keys.
    `basis_overrides` (speed_m_s, fraction_reaching, n_propellers) replace the scenarios' values."""
    differing = _differing({run: scenario for run, (_, scenario, _) in runs.items()})
    if differing and not pool:
        raise InputError(
            "run_or_study_dir",
            f"{len(runs)} runs below {str(root)!r} differ in {', '.join(differing)}",
            allowed="runs that differ only in seed and field, or pool=True (--pool) to pool them anyway",
        )
    exposures, missing = {}, []
    for run, (run_dir, scenario, distance) in runs.items():
        basis = _basis(scenario, basis_overrides, str(run_dir / "scenario.resolved.toml"))
        if distance is None:
            missing.append(run)
        else:
            exposures[run] = RunExposure(distance, basis)
    run_dirs = {run: run_dir for run, (run_dir, _, _) in runs.items()}
    profiles = {(scenario or {}).get("profile", "default") for _, scenario, _ in runs.values()}
    profile = "thesis" if profiles == {"thesis"} else "default"
    return RunInputs(cusps, None if missing else exposures, run_dirs, differing, tuple(missing), profile)
