"""Study designs: a base scenario, sweeps of parameters, Monte Carlo fields, one root seed.

A study file (TOML)::

    name = "toughness"
    root_seed = 2023
    n_fields = 4                 # random floe fields per design point (Monte Carlo)
    common_fields = true         # the same n_fields fields at every design point (as the thesis' Fig. 1)
    base = "reference.toml"      # or an inline [base] table; omitted: the reference scenario

    [[sweeps]]                   # one group; groups are run one after the other (one-factor-at-a-time)
    name = "fracture toughness"
    mode = "factorial"           # or "zip" (parameters advance together)
    parameters = {"ice.fracture_toughness_pa_sqrt_m" = [120e3, 145.7e3, 230e3]}

Seeds: run i gets ``SeedSequence(root_seed, spawn_key=(i,))`` — the run's scenario seed is the first 32-bit
word of its state, so any run can be recomputed alone whatever the scheduling order. With ``common_fields``
the spawn key is the field index instead of the run index, so every design point sees the same fields
(the thesis compares parameters on the same four fields); documented in docs/studies.md.
"""

from __future__ import annotations

import copy
import itertools
import json
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from floebreak.config.scenario import REFERENCE_TOML, SEED_MAX, Scenario, allowed_interval
from floebreak.errors import InputError
from floebreak.io.toml_text import loads_toml

# random fields per design point: the Monte Carlo error falls as 1/√n, to 1 % of one field's scatter at
# 10 000; each field is a whole run
N_FIELDS = (1, 10_000)


class Sweep(BaseModel):
    """One group of swept parameters (dotted scenario keys → lists of values)."""

    model_config = ConfigDict(extra="forbid")
    name: str = Field("", description="label of the group in tables and figures")
    mode: Literal["factorial", "zip"] = Field("factorial", description="full factorial or zipped lists")
    parameters: dict[str, list[Any]] = Field(description="dotted scenario key → list of values")


class StudySpec(BaseModel):
    """A study: base scenario + sweep groups + Monte Carlo fields + root seed."""

    model_config = ConfigDict(extra="forbid")
    name: str = Field("study", description="study name")
    root_seed: int = Field(
        2023, ge=0, le=SEED_MAX, description="root of numpy.random.SeedSequence for all runs, 0 … 2⁶³ − 1"
    )
    n_fields: int = Field(
        4,
        ge=N_FIELDS[0],
        le=N_FIELDS[1],
        description="random floe fields per design point (Monte Carlo), 1 … 10 000 (the error falls as 1/√n)",
    )
    common_fields: bool = Field(True, description="same fields at every design point (field-index seeds)")
    base: dict[str, Any] | str | None = Field(
        None, description="inline scenario table, or a scenario file path"
    )
    sweeps: list[Sweep] = Field(default_factory=list, description="sweep groups, run one after the other")


@dataclass(frozen=True)
class RunSpec:
    """One run of a study: its index, design point, field index, seed and full scenario (plain dict)."""

    index: int
    group: str
    point: dict[str, Any]  # the swept parameters of this run
    field_index: int
    seed: int
    scenario: dict[str, Any]

    @property
    def run_name(self) -> str:
        return f"run-{self.index:05d}"


def set_dotted(data: dict[str, Any], key: str, value: Any) -> None:
    node = data
    parts = key.split(".")
    for part in parts[:-1]:
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise InputError("sweeps.parameters", f"{key!r}: {part!r} is not a table", allowed="a dotted key")
    node[parts[-1]] = value


def run_seed(root_seed: int, key: int) -> int:
    """The scenario seed for spawn key `key` (run index, or field index with common fields)."""
    state = np.random.SeedSequence(root_seed, spawn_key=(key,)).generate_state(1, dtype=np.uint32)
    return int(state[0])


def check_n_fields(n_fields: Any) -> int:
    """`n_fields` (random fields per design point) if it is an integer in `N_FIELDS`, else InputError."""
    low, high = N_FIELDS
    if isinstance(n_fields, bool) or not isinstance(n_fields, int) or not low <= n_fields <= high:
        raise InputError(
            "n_fields", f"{n_fields!r} is outside [{low}, {high}]", value=n_fields, allowed=f"[{low}, {high}]"
        )
    return n_fields


def load_study(path: str | Path) -> tuple[StudySpec, Path]:
    path = Path(path)
    try:
        data = loads_toml(path.read_text(encoding="utf-8-sig"), "study", str(path))
    except OSError as error:
        raise InputError(
            "study", f"cannot read {str(path)!r}: {error}", allowed="a readable TOML file"
        ) from None
    except tomllib.TOMLDecodeError as error:
        raise InputError("study", f"{path}: malformed TOML: {error}", allowed="a TOML file") from None
    return study_from_dict(data), path.absolute().parent  # absolute: workers may run elsewhere


def study_from_dict(data: Mapping[str, Any]) -> StudySpec:
    try:
        spec = StudySpec.model_validate(data)
    except ValidationError as error:
        first = error.errors()[0]
        key = ".".join(str(p) for p in first["loc"])
        allowed = allowed_interval(StudySpec.model_json_schema(), first["loc"]) or "see docs/studies.md"
        value = first.get("input")
        message = first["msg"] if isinstance(value, dict | list) else f"{first['msg']} (got {value!r})"
        raise InputError(key or "study", message, value=value, allowed=allowed) from None
    return spec


def base_scenario_dict(spec: StudySpec, base_dir: Path | None) -> tuple[dict[str, Any], Path | None]:
    if spec.base is None:
        return tomllib.loads(REFERENCE_TOML), None
    if isinstance(spec.base, str):
        path = Path(spec.base) if base_dir is None else base_dir / spec.base
        try:
            return loads_toml(path.read_text(encoding="utf-8-sig"), "base", str(path)), path.parent
        except (OSError, tomllib.TOMLDecodeError) as error:
            raise InputError(
                "base", f"cannot read scenario {str(path)!r}: {error}", allowed="a scenario TOML"
            ) from None
    return copy.deepcopy(spec.base), base_dir


def design_points(sweep: Sweep) -> list[dict[str, Any]]:
    if not sweep.parameters:
        raise InputError(
            "sweeps.parameters", f"sweep {sweep.name!r} is empty", allowed="at least one parameter"
        )
    keys = list(sweep.parameters)
    lists = [sweep.parameters[k] for k in keys]
    for key, values in zip(keys, lists, strict=True):
        if not values:
            raise InputError(f"sweeps.parameters.{key}", "empty list of values", allowed="at least one value")
    if sweep.mode == "zip":
        if len({len(v) for v in lists}) != 1:
            raise InputError(
                "sweeps.mode",
                f"zip sweep {sweep.name!r} has lists of different lengths",
                allowed="equal lengths",
            )
        combos = list(zip(*lists, strict=True))
    else:
        combos = list(itertools.product(*lists))
    return [dict(zip(keys, combo, strict=True)) for combo in combos]


@dataclass(frozen=True)
class Membership:
    """A design point × field of a sweep group and the run that computes it (shared runs appear twice)."""

    group: str
    point: dict[str, Any]
    field_index: int
    run_name: str


def expand(spec: StudySpec, base_dir: Path | None = None) -> tuple[list[RunSpec], list[Membership]]:
    """All runs of the study, validated before anything runs (first offending combination is reported).

    A study without sweeps is the base scenario on `n_fields` fields. Design points repeated across groups
    (e.g. the reference value in every one-factor sweep) run once; every group still lists them.
    """
    base, scenario_dir = base_scenario_dict(spec, base_dir)
    groups = [(s.name or f"sweep {i + 1}", design_points(s)) for i, s in enumerate(spec.sweeps)] or [
        ("base", [{}])
    ]
    runs: list[RunSpec] = []
    members: list[Membership] = []
    seen: dict[str, str] = {}
    for group, points in groups:
        for point in points:
            for field_index in range(spec.n_fields):
                scenario = copy.deepcopy(base)
                for key, value in point.items():
                    set_dotted(scenario, key, value)
                index = len(runs)
                seed = run_seed(spec.root_seed, field_index if spec.common_fields else index)
                scenario["seed"] = seed
                try:
                    validated = Scenario.from_dict(scenario, base_dir=scenario_dir)
                except InputError as error:
                    raise InputError(
                        error.field,
                        f"design point {json.dumps(point)} of {group!r}: {error}",
                        value=point,
                        allowed=error.allowed,
                    ) from None
                key = validated.resolved().hash()
                if key not in seen:
                    run = RunSpec(index, group, point, field_index, seed, validated.to_dict())
                    runs.append(run)
                    seen[key] = run.run_name
                members.append(Membership(group, point, field_index, seen[key]))
    return runs, members


def thesis_study(n_fields: int = 4, profile: str = "default", root_seed: int = 2023) -> StudySpec:
    """Thesis §5.3 (Tables 5–8): one-factor sweeps around the reference configuration, on fields of the
    thesis' inferred size (`field_size`: 385 m × 100 m)."""
    from floebreak.studies.field_size import thesis_scenario

    base = thesis_scenario()
    base["profile"] = profile
    return StudySpec(
        name=f"thesis §5.3 ({profile} profile)",
        root_seed=root_seed,
        n_fields=n_fields,
        common_fields=True,
        base=base,
        sweeps=[
            Sweep(
                name="fracture toughness",
                parameters={"ice.fracture_toughness_pa_sqrt_m": [120e3, 145.7e3, 230e3]},
            ),
            Sweep(
                name="crack criterion",
                parameters={
                    "failure.cracking.criterion": [
                        "point_load",
                        "line_load",
                        "tensile_stress",
                        "flexural_stress",
                    ]
                },
            ),
            Sweep(name="ice thickness", parameters={"ice.thickness_m": [0.8, 1.0, 1.2]}),
            Sweep(
                name="random thickness",
                mode="zip",
                parameters={"ice.thickness_m": [None], "ice.thickness_range_m": [[0.75, 1.25]]},
            ),
            Sweep(
                name="size-effect law", parameters={"failure.cracking.size_effect_law": ["BZ", "BZ1", "BZ2"]}
            ),
        ],
    )
