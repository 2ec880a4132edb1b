"""Voyages: an ice observation log → a study design, one point per period → pooled propeller loads.

Each period of the log (`floebreak.studies.voyage_log`) becomes a user observation (concentration, mean
thickness,
diameter classes) simulated on `n_fields` random fields; the periods are one zipped sweep of a study, so a
voyage runs on the study machinery (`floebreak.studies.runner`: resumable, local pool or Dask). The rules,
documented in docs/studies.md ("Voyages"):

- **Distance.** A period sails D = v · T: v from the log's speed column, else the `speed_m_s` option, else
  the scenario's ``ship.speed_m_s`` (default 3 m/s, the ship speed the thesis assumes, §6.3, Eq. 28). Each
  period's scenario carries its speed, so the runs' rates (`floebreak propeller`) use it too.
- **Simulated length.** Each field is L = min(D, `max_length_m`) long (default `DEFAULT_MAX_LENGTH_M` =
  400 m, about the thesis' inferred field length, docs/validation.md). A simulated cusp of the period then
  stands for w = D / (n · L) cusps of the voyage (n = fields completed): counts are scaled by the distance.
- **Width.** W = B + 2 d_max + 2 m: the ship's band (beam B of the bow as built for the period's thickness)
  plus, on each side, the largest floe diameter of the period d_max — every floe that can reach into the
  band lies wholly inside the field, so the field's edges never touch the band — and a margin m =
  `FIELD_MARGIN_M`. (Thesis reference: 21.7 + 2 · 15 + 2 · 5 ≈ 62 m against its 50 m.)
- **Generator.** circles (observed diameter classes) by default; a period whose circles field cannot be
  generated on any of its fields (target concentration not reached, or whole floes of the largest class
  too coarse for the field) uses voronoi for all its fields; the choice and the reason are recorded.
- **Same fields.** Fields are common fields (seed from the field index, generated once in the process
  that runs the voyage): two periods with identical conditions share their runs.
"""

from __future__ import annotations

import copy
import hashlib
import json
import tomllib
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from floebreak.config.scenario import (
    FIELD_LENGTH_M,
    REFERENCE_TOML,
    SEED_MAX,
    SPEED_M_S,
    Scenario,
    apply_overrides,
)
from floebreak.errors import InputError, require_range
from floebreak.studies.design import Membership, StudySpec, Sweep, check_n_fields, expand
from floebreak.studies.voyage_log import LogPeriod, VoyageLog
from floebreak.studies.voyage_results import FIELD_MARGIN_M, VoyageAnalysis

DEFAULT_MAX_LENGTH_M = 400.0  # about the thesis' §5.3 field length (385–447 m inferred, docs/validation.md)
VOYAGE_FILE = "voyage.json"
# scenario keys the log sets per period (a --set of them is refused)
LOG_KEYS = (
    "seed",
    "field.observation",
    "field.concentration",
    "field.diameter_classes_m",
    "field.percentages",
    "field.file",
    "field.floes",
    "field.length_m",
    "field.width_m",
    "field.generator",
    "ice.thickness_m",
    "ice.thickness_range_m",
)


@dataclass(frozen=True)
class PeriodPlan:
    """What one log period is simulated as: speed (and where it came from), distance, field size."""

    index: int
    period: LogPeriod
    speed_m_s: float
    speed_source: str  # "log", "option" or "scenario" (ship.speed_m_s, default or --set)
    distance_m: float
    simulated_length_m: float
    field_width_m: float
    beam_m: float

    @property
    def largest_diameter_m(self) -> float:
        return max(self.period.diameter_classes_m)


def base_scenario(overrides: Iterable[str] = ()) -> dict[str, Any]:
    """The reference scenario without its field source and thickness, with `--set` overrides applied.

    Keys the log sets per period (`LOG_KEYS`) are refused."""
    overrides = list(overrides)
    for expression in overrides:
        key = expression.partition("=")[0].strip()
        if key in LOG_KEYS:
            raise InputError(
                "--set",
                f"{key} is set per period by the log (or by --seed)",
                value=expression,
                allowed="ship.*, failure.*, profile, ice material keys, field.clustering, "
                "field.floe_area_factor",
            )
    base = tomllib.loads(REFERENCE_TOML)
    for key in ("observation", "length_m", "width_m", "generator"):
        base["field"].pop(key, None)
    base["ice"].pop("thickness_m", None)
    return apply_overrides(base, overrides)


def period_scenario(base: dict[str, Any], plan: PeriodPlan, generator: str = "circles") -> dict[str, Any]:
    """The scenario of one period (pure): the base with the period's observation, thickness and field."""
    scenario = copy.deepcopy(base)
    period = plan.period
    scenario.setdefault("field", {}).update(
        {
            "concentration": period.concentration,
            "diameter_classes_m": list(period.diameter_classes_m),
            "percentages": list(period.percentages),
            "length_m": plan.simulated_length_m,
            "width_m": plan.field_width_m,
            "generator": generator,
        }
    )
    scenario.setdefault("ice", {})["thickness_m"] = period.mean_thickness_m
    scenario.setdefault("ship", {})["speed_m_s"] = plan.speed_m_s
    return scenario


def _ship_scenario(base: dict[str, Any], thickness_m: float) -> Scenario:
    """The resolved base scenario at `thickness_m` (for the bow and the ship's default speed)."""
    data = copy.deepcopy(base)
    data.setdefault("ice", {})["thickness_m"] = thickness_m
    # any valid field source: the bow reads only the ship section and the thickness
    data.setdefault("field", {}).update(
        {"concentration": 0.5, "diameter_classes_m": [1.0], "percentages": [100.0]}
    )
    return Scenario.from_dict(data).resolved()


def plan_voyage(
    log: VoyageLog,
    base: dict[str, Any],
    speed_m_s: float | None = None,
    max_length_m: float = DEFAULT_MAX_LENGTH_M,
) -> list[PeriodPlan]:
    """Speed, distance and field size of every period (see the module docstring for the rules)."""
    if speed_m_s is not None:
        require_range("speed_m_s", speed_m_s, low=SPEED_M_S[0], high=SPEED_M_S[1], unit="m/s")
    require_range("max_length_m", max_length_m, low=0.0, high=FIELD_LENGTH_M[1], unit="m")
    from floebreak.app.run import build_bow

    plans = []
    beams: dict[float, float] = {}
    ships: dict[float, Scenario] = {}  # one validated scenario per thickness, not per period
    for index, period in enumerate(log.periods):
        if period.mean_thickness_m not in ships:
            ships[period.mean_thickness_m] = _ship_scenario(base, period.mean_thickness_m)
        ship = ships[period.mean_thickness_m]
        if period.speed_m_s is not None:
            speed, source = period.speed_m_s, "log"
        elif speed_m_s is not None:
            speed, source = speed_m_s, "option"
        else:
            speed, source = ship.ship.speed_m_s, "scenario"
        distance = speed * period.duration_h * 3600.0
        if period.mean_thickness_m not in beams:  # the beam of the bow as built for the thickness
            beams[period.mean_thickness_m] = 2.0 * build_bow(ship).half_breadth_m
        beam = beams[period.mean_thickness_m]
        width = beam + 2.0 * max(period.diameter_classes_m) + 2.0 * FIELD_MARGIN_M
        plans.append(
            PeriodPlan(index, period, speed, source, distance, min(distance, max_length_m), width, beam)
        )
    return plans


def voyage_spec(
    name: str, plans: list[PeriodPlan], base: dict[str, Any], n_fields: int, seed: int, generators: list[str]
) -> StudySpec:
    """The study of a voyage: one zipped sweep, one design point per period, `n_fields` common fields."""
    scenarios = [period_scenario(base, plan, g) for plan, g in zip(plans, generators, strict=True)]
    keys = {
        "field.concentration": ("field", "concentration"),
        "field.diameter_classes_m": ("field", "diameter_classes_m"),
        "field.percentages": ("field", "percentages"),
        "field.length_m": ("field", "length_m"),
        "field.width_m": ("field", "width_m"),
        "field.generator": ("field", "generator"),
        "ice.thickness_m": ("ice", "thickness_m"),
        "ship.speed_m_s": ("ship", "speed_m_s"),
    }
    parameters = {key: [s[a][b] for s in scenarios] for key, (a, b) in keys.items()}
    return StudySpec(
        name=name,
        root_seed=seed,
        n_fields=n_fields,
        common_fields=True,
        base=base,
        sweeps=[Sweep(name="voyage", mode="zip", parameters=parameters)],
    )


def period_members(members: list[Membership], n_periods: int, n_fields: int) -> list[list[Membership]]:
    """The members of each period: `expand` lists them period by period, field by field."""
    if len(members) != n_periods * n_fields:
        raise RuntimeError(f"{len(members)} members for {n_periods} periods × {n_fields} fields")
    return [members[i * n_fields : (i + 1) * n_fields] for i in range(n_periods)]


def choose_generators(
    name: str,
    plans: list[PeriodPlan],
    base: dict[str, Any],
    n_fields: int,
    seed: int,
    fields_dir: Path,
    progress: Callable[[int], None] | None = None,
) -> list[tuple[str, str]]:
    """(generator, reason) per period: circles when every field of the period can be generated with it
    (the fields are generated and saved in `fields_dir` on the way), else voronoi with the first error."""
    from floebreak.studies.runner import generate_common_field

    spec = voyage_spec(name, plans, base, n_fields, seed, ["circles"] * len(plans))
    runs, members = expand(spec)
    by_name = {run.run_name: run for run in runs}
    choices = []
    for index, group in enumerate(period_members(members, len(plans), n_fields)):
        choice, made = ("circles", ""), []
        for member in group:
            try:
                made.append(generate_common_field(by_name[member.run_name].scenario, fields_dir))
            except InputError as error:  # ConcentrationError, or a field too small for whole large floes
                choice = ("voronoi", f"circles: {error}")
                for path in made:  # unused now (a period with the same conditions fails the same way)
                    if path:
                        Path(path).unlink(missing_ok=True)
                break
            except Exception:  # a bug: the run meets it again in its worker, which records it
                break
        choices.append(choice)
        if progress:
            progress(index + 1)
    return choices


def log_digest(log: VoyageLog) -> str:
    """SHA-256 of the validated periods (what the voyage depends on, not the file's formatting)."""
    rows = [
        [
            p.start_utc.isoformat(),
            p.end_utc.isoformat(),
            p.concentration,
            p.mean_thickness_m,
            list(p.diameter_classes_m),
            list(p.percentages),
            p.speed_m_s,
            p.propeller_rpm,
            p.propeller_pitch_percent,
        ]
        for p in log.periods
    ]
    return hashlib.sha256(json.dumps(rows).encode()).hexdigest()


def check_out_dir(out: Path, identity: dict[str, Any]) -> None:
    """Refuse an `out` that is neither new, empty, nor this voyage's directory (resume)."""
    if not out.exists():
        return
    if not out.is_dir():
        raise InputError("out", f"{str(out)!r} is a file", allowed="a directory path")
    voyage_file = out / VOYAGE_FILE
    if voyage_file.exists():
        try:
            recorded = json.loads(voyage_file.read_text(encoding="utf-8")).get("identity")
        except (OSError, json.JSONDecodeError):
            recorded = None
        if recorded != json.loads(json.dumps(identity)):
            raise InputError(
                "out",
                f"{str(out)!r} holds another voyage (other log, fields, seed or settings)",
                allowed="a new directory, or this voyage's own to resume it",
            )
    elif any(out.iterdir()):
        raise InputError(
            "out", f"{str(out)!r} exists and is not a voyage directory", allowed="a new directory"
        )


def period_record(plan: PeriodPlan, generator: tuple[str, str], runs: list[str]) -> dict[str, Any]:
    """A period's entry in voyage.json: the log row, the plan, the generator and its runs."""
    period = plan.period
    return {
        "index": plan.index,
        "row": period.row,
        "label": period.label,
        "start_utc": period.start_utc.isoformat(),
        "end_utc": period.end_utc.isoformat(),
        "duration_h": period.duration_h,
        "concentration": period.concentration,
        "mean_thickness_m": period.mean_thickness_m,
        "diameter_classes_m": list(period.diameter_classes_m),
        "percentages": list(period.percentages),
        "propeller_rpm": period.propeller_rpm,
        "propeller_pitch_percent": period.propeller_pitch_percent,
        "speed_m_s": plan.speed_m_s,
        "speed_source": plan.speed_source,
        "distance_m": plan.distance_m,
        "simulated_length_m": plan.simulated_length_m,
        "field_width_m": plan.field_width_m,
        "beam_m": plan.beam_m,
        "generator": generator[0],
        "generator_reason": generator[1],
        "runs": runs,
    }


def _write_json(path: Path, document: dict[str, Any]) -> None:
    from floebreak.io.atomic import atomic_path

    with atomic_path(path, field="out") as temp:
        temp.write_text(json.dumps(document, indent=2, default=str) + "\n", encoding="utf-8")


@dataclass(frozen=True)
class VoyageSetup:
    """A validated voyage, ready to run: the log, its periods' plans, the base scenario and the options."""

    log: VoyageLog
    plans: list[PeriodPlan]
    base: dict[str, Any]
    name: str
    n_fields: int
    seed: int
    identity: dict[str, Any]
    analysis: VoyageAnalysis = VoyageAnalysis()


def prepare_voyage(
    log: VoyageLog,
    *,
    n_fields: int = 4,
    seed: int = 2023,
    overrides: Iterable[str] = (),
    speed_m_s: float | None = None,
    max_length_m: float = DEFAULT_MAX_LENGTH_M,
    analysis: VoyageAnalysis = VoyageAnalysis(),  # noqa: B008 - frozen dataclass
) -> VoyageSetup:
    """Validate the options and every period's scenario; nothing is written. `analysis`: the propeller
    (and shaft) options of the results, outside the identity (they change ``results/`` only)."""
    check_n_fields(n_fields)
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= SEED_MAX:
        raise InputError("seed", f"{seed!r} is outside [0, 2⁶³ − 1]", value=seed, allowed="[0, 2⁶³ − 1]")
    overrides = list(overrides)
    base = base_scenario(overrides)
    plans = plan_voyage(log, base, speed_m_s, max_length_m)
    name = f"voyage {Path(log.source).name}"
    expand(voyage_spec(name, plans, base, n_fields, seed, ["circles"] * len(plans)))  # validates all
    identity = {
        "log_sha256": log_digest(log),
        "n_fields": n_fields,
        "seed": seed,
        "overrides": overrides,
        "speed_m_s": speed_m_s,
        "max_length_m": max_length_m,
    }
    return VoyageSetup(log, plans, base, name, n_fields, seed, identity, analysis.checked())


def run_voyage(
    setup: VoyageSetup,
    out: str | Path,
    executor=None,
    progress: Callable[[str, Any], None] | None = None,
    profile=None,
) -> dict[str, Any]:
    """Simulate every period into the voyage directory `out` (resumable) and write its results
    (`profile`: an `OperatingProfile` for the rule-form extrapolation, or None).

    `progress(stage, value)` is called with ("fields", periods whose generator is chosen) and ("runs",
    `StudyProgress`). Returns the results' summary (`write_voyage_results`)."""
    from floebreak.studies.runner import run_study
    from floebreak.studies.voyage_results import write_voyage_results

    out = Path(out)
    check_out_dir(out, setup.identity)
    out.mkdir(parents=True, exist_ok=True)
    document = {
        "log": Path(setup.log.source).name,
        "identity": setup.identity,
        "columns": list(setup.log.columns),
        "analysis": setup.analysis.as_dict(),  # the results' propeller options (not the identity)
    }
    _write_json(out / VOYAGE_FILE, document)
    n_fields, plans = setup.n_fields, setup.plans
    generators = choose_generators(
        setup.name,
        plans,
        setup.base,
        n_fields,
        setup.seed,
        out / "fields",
        (lambda i: progress("fields", i)) if progress else None,
    )
    spec = voyage_spec(setup.name, plans, setup.base, n_fields, setup.seed, [g for g, _ in generators])
    runs, members = expand(spec)
    groups = period_members(members, len(plans), n_fields)
    document["periods"] = [
        period_record(plan, generator, [m.run_name for m in group])
        for plan, generator, group in zip(plans, generators, groups, strict=True)
    ]
    _write_json(out / VOYAGE_FILE, document)
    on_run = (lambda state: progress("runs", state)) if progress else None
    state = run_study(spec, runs, members, out, executor, on_run, run_figures=False)
    summary = write_voyage_results(out, profile, setup.analysis)
    summary["failures"] = state.failures
    return summary
