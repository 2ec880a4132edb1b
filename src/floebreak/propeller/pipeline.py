"""Propeller analysis of a run, study or voyage (pure): cusps → force/torque per cusp → spectra, rates,
rule-form fits, comparison with a measured series, rule check. Returns a `PropellerResult`; writing is in
`floebreak.output.propeller_files`, drawing in `floebreak.plotting.propeller`. See docs/propeller.md.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.propeller.cusps import (
    DEFAULT_CLASS_EDGES_M3,
    check_class_edges,
    class_means,
    cusp_columns,
    volume_class,
)
from floebreak.propeller.flow_transport import flow_draws_of_runs, flow_of_runs
from floebreak.propeller.iceclass import WEIBULL_SHAPE, IceClassLoads, check_polar_class, ur_i3_loads
from floebreak.propeller.interpolation import check_options
from floebreak.propeller.load_models import (
    TRANSPORTS,
    check_choice,
    drive_rated_torque_n_m,
    engaged_intervals,
    extrapolation_warnings,
    force_warnings,
    override_warning,
    placement_text,
    torque_warnings,
    transport_of_runs,
    transport_summary,
)
from floebreak.propeller.loads import get_load_model, load_model_names
from floebreak.propeller.loads.fem import DEFAULT_VOLUME_BASIS, VOLUME_BASES, FemTable, fem_table_dict
from floebreak.propeller.measured import TorqueSeries
from floebreak.propeller.rates import RateBasis, RunExposure, check_exposures, weighted_exceedance
from floebreak.propeller.reach_warnings import no_load_reason, no_load_warning
from floebreak.propeller.ruleform import BasquinCurve, OperatingProfile, RuleArrangement
from floebreak.propeller.spec import PropellerSpec
from floebreak.propeller.spectra import (
    DENSITY_THRESHOLD_PER_KNM,
    bin_edges,
    density,
    fitting_width,
    pitch_label,
    ranges_above,
    spectra_dataset,
    spectrum_edges,
    torque_ranges_above,
)
from floebreak.propeller.spread import SPREAD_DRAWS, check_draws, load_spread
from floebreak.propeller.summary import build_summary, finite_range
from floebreak.propeller.transport import TransportSettings

__all__ = [
    "PropellerResult",
    "analyse_cusp_loads",
    "load_spectra",
    "pitch_label",
    "torque_ranges_above",
]


@dataclass(frozen=True)
class CuspAmplitudes:
    """Per-cusp load amplitudes at one pitch in transit order: run, bow x [m], force [N], torque [N·m]
    (signed as the FEM table), whether the cusp lay beyond the table, and the loads per cusp on one
    propeller (`weight`: fraction reaching / number of propellers). For shaft-line and voyage models."""

    run_id: np.ndarray
    bow_x_m: np.ndarray
    force_n: np.ndarray
    torque_nm: np.ndarray
    beyond_table: np.ndarray
    weight: np.ndarray


@dataclass(frozen=True)
class MeasuredSpectrum:
    """Density of a measured shaft-torque series on bins [kN·m] and its ranges above the threshold."""

    series: TorqueSeries
    edges_knm: np.ndarray
    density_per_knm: np.ndarray
    intervals_knm: list


@dataclass(frozen=True)
class PropellerResult:
    """Everything `analyse_cusp_loads` computes; nothing is written. `loads` is the per-cusp table in
    transit order (run, then bow position); `spectra` the CF xarray Dataset (densities, counts and, with
    exposures, rates per hour and per km); `summary` the JSON-ready summary (without provenance)."""

    options: dict[str, Any]
    propeller: PropellerSpec
    tables: dict[float, FemTable]
    loads: dict[str, np.ndarray]
    class_tables: dict[str, dict[str, np.ndarray]]
    spectra: Any
    exceedance: dict[str, dict[str, np.ndarray]]
    summary: dict[str, Any]
    rule: IceClassLoads | None = None
    measured: MeasuredSpectrum | None = None
    exposures: dict[str, RunExposure] = field(default_factory=dict)

    @property
    def pitches(self) -> tuple[float, ...]:
        """The pitches [%] with per-cusp loads: the FEM tables' or the milling model's."""
        return tuple(self.options["pitches"])

    def amplitudes(self, pitch_percent: float) -> CuspAmplitudes:
        """The per-cusp amplitudes at one pitch (transit order, see `CuspAmplitudes`)."""
        if float(pitch_percent) not in self.pitches:
            raise InputError(
                "pitch_percent", f"no loads at pitch {pitch_percent!r}", allowed=str(list(self.pitches))
            )
        label = pitch_label(float(pitch_percent))
        return CuspAmplitudes(
            self.loads["run_id"],
            self.loads["bow_x_m"],
            self.loads[f"force_n_{label}"],
            self.loads[f"torque_nm_{label}"],
            self.loads[f"beyond_table_{label}"],
            self.loads["loads_per_propeller"],
        )


def load_spectra(
    loads: dict[str, np.ndarray],
    tables,
    force_bin_kn: float = 10.0,
    torque_bin_knm: float = 10.0,
    attrs: dict | None = None,
):
    """Spectra dataset (pure) of |F| [kN] and |Q| [kN·m] per pitch (`tables`: the FEM tables or the
    pitches) from a per-cusp table: each run's density and their mean, every run weighted equally (thesis
    Figs. 32–33; see `spectra_dataset`)."""
    run_id = loads["run_id"]
    runs = sorted(set(run_id.tolist()))
    force_kn = {}
    torque_knm = {}
    for pitch in tables:
        label = pitch_label(pitch)
        f, q = loads[f"force_n_{label}"], loads[f"torque_nm_{label}"]
        force_kn[pitch] = {r: np.abs(f[run_id == r]) / 1e3 for r in runs}
        torque_knm[pitch] = {r: np.abs(q[run_id == r]) / 1e3 for r in runs}
    return spectra_dataset(force_kn, torque_knm, force_bin_kn, torque_bin_knm, attrs=attrs)


def transit_order(columns: dict[str, np.ndarray]) -> np.ndarray:
    """Indices sorting the cusps by run (first appearance), then bow position (stable; NaN last)."""
    run_id = columns["run_id"]
    first = {r: i for i, r in reversed(list(enumerate(run_id.tolist())))}
    rank = np.array([first[r] for r in run_id.tolist()], dtype=np.int64)
    return np.lexsort((columns["bow_x_m"], rank))


def _measured_spectrum(series: TorqueSeries, torque_bin_knm: float) -> MeasuredSpectrum:
    q_knm = series.torque_nm / 1e3
    edges = bin_edges(q_knm, fitting_width(q_knm, torque_bin_knm))
    dens = density(q_knm, edges)
    return MeasuredSpectrum(series, edges, dens, ranges_above(edges, dens, DENSITY_THRESHOLD_PER_KNM))


def _table_info(loads, tables, pitches, rule) -> dict[str, dict]:
    """Per pitch: table points (FEM), counts beyond the table / without load / with reversed sign, ranges,
    and the rule flags (added to `loads`)."""
    info = {}
    n = loads["run_id"].size
    for pitch in pitches:
        table = tables.get(pitch)
        label = pitch_label(pitch)
        f, q = loads[f"force_n_{label}"], loads[f"torque_nm_{label}"]
        n_beyond = int(loads[f"beyond_table_{label}"].sum())
        sign_f, sign_q = (1.0, -1.0) if table is None else (np.sum(table.force_n), np.sum(table.torque_nm))
        info[label] = {
            "pitch_percent": pitch,
            "source": "blade milling model" if table is None else table.source,
            "dimensions": [] if table is None else list(table.dimensions),
            "max_volume_m3": None if table is None else table.max_volume_m3,
            "n_beyond_table": n_beyond,
            "fraction_beyond_table": n_beyond / n if n else 0.0,
            "n_without_load": int((~np.isfinite(f)).sum()),
            "n_sign_reversed_force": int(np.sum(np.sign(f[np.isfinite(f)]) == -np.sign(sign_f))),
            "n_sign_reversed_torque": int(np.sum(np.sign(q[np.isfinite(q)]) == -np.sign(sign_q))),
            "force_range_kn": finite_range(np.abs(f) / 1e3),
            "torque_range_knm": finite_range(np.abs(q) / 1e3),
        }
        if rule is not None:
            loads[f"exceeds_backward_force_{label}"] = np.abs(f) > rule.backward_force_n
            loads[f"exceeds_forward_force_{label}"] = np.abs(f) > rule.forward_force_n
            loads[f"exceeds_max_torque_{label}"] = np.abs(q) > rule.max_torque_nm
            info[label]["rule_exceedances"] = {
                k: int(loads[f"{k}_{label}"].sum())
                for k in ("exceeds_backward_force", "exceeds_forward_force", "exceeds_max_torque")
            }
    return info


def _class_tables(loads, edges_m3) -> dict[str, dict[str, np.ndarray]]:
    keys = ("bbox_longer_m", "bbox_shorter_m", "thickness_m", "box_volume_m3")
    run_id = loads["run_id"]
    out = {
        r: class_means(*(loads[k][run_id == r] for k in keys), edges_m3) for r in sorted(set(run_id.tolist()))
    }
    out["ALL"] = class_means(*(loads[k] for k in keys), edges_m3)
    return out


def _add_rates(ds, loads, exposures: dict[str, RunExposure]) -> tuple[Any, dict[str, dict[str, np.ndarray]]]:
    """Rates per bin (per hour in ice and per km on one propeller) into `ds`, and exceedance tables.

    Counts of all runs are summed, each loaded cusp weighted by its run's share per propeller (f / n_p with
    an override, else 1 / n_p; cusps that reach no propeller carry no load and weigh 0), and divided by the
    summed hours and km of the runs (time-weighted pooling)."""
    share = np.array([exposures[r].basis.share_per_propeller for r in ds["run"].values.tolist()])
    hours = sum(e.hours for e in exposures.values())  # runs without cusps too
    km = sum(e.km for e in exposures.values())
    weight = np.array([exposures[r].basis.share_per_propeller for r in loads["run_id"].tolist()])
    weight = np.where(loads["reaches_propeller"], weight, 0.0)
    loads["loads_per_propeller"] = weight
    tables: dict[str, dict[str, np.ndarray]] = {}
    for quantity, axis, scale in (("force", "force_kn", 1e3), ("torque", "torque_knm", 1e3)):
        expected = np.einsum("rpb,r->pb", ds[f"{quantity}_count_run"].values.astype(float), share)
        for per, total, unit in (("hour", hours, "h-1"), ("km", km, "km-1")):
            ds[f"{quantity}_rate_per_{per}"] = (
                ("pitch", axis),
                expected / total,
                {"units": unit, "long_name": f"{quantity} loads per bin on one propeller per {per} in ice"},
            )
        levels = spectrum_edges(ds, quantity)[:-1]
        for pitch in ds["pitch"].values:
            column = "force_n" if quantity == "force" else "torque_nm"
            n = weighted_exceedance(loads[f"{column}_{pitch_label(float(pitch))}"] / scale, weight, levels)
            tables[f"{quantity}_{pitch_label(float(pitch))}"] = {
                "level": levels,
                "per_hour": n / hours,
                "per_km": n / km,
            }
    return ds, tables


def _cusp_loads(columns, tables, options, propeller, speed_m_s, engaged=None) -> dict[str, np.ndarray]:
    """The per-cusp table of the cusps (in transit order) by the load model, with their volume class;
    loads per cusp on one propeller NaN until a time base is known (`_add_rates`). `engaged`: the milling
    model's engaged intervals (r_in, r_out) per cusp (`engaged_intervals`; NaN: tip placement), kept as
    the columns engaged_inner_radius_m, engaged_outer_radius_m."""
    model = get_load_model(options["load_model"])
    loads = model.cusp_loads(columns, tables, options, propeller, speed_m_s, engaged)
    loads["volume_class"] = volume_class(loads["box_volume_m3"], options["volume_class_edges_m3"])
    loads["loads_per_propeller"] = np.full(loads["run_id"].size, math.nan)
    return loads


def _placed_loads(columns, tables, options, propeller, speed, transports) -> tuple[dict, str | None]:
    """The per-cusp table (`_cusp_loads`) with the milling model's blocks on their engaged intervals where
    the transport moved the run (`engaged_intervals`), and the placement's text (None for FEM)."""
    n_runs = len(set(columns["run_id"].tolist()))
    on_blade = get_load_model(options["load_model"]).places_on_blade
    placement = placement_text(on_blade, len(transports), n_runs - len(transports))
    engaged = engaged_intervals(transports, columns["run_id"].size, propeller) if placement else None
    return _cusp_loads(columns, tables, options, propeller, speed, engaged), placement


def _reaching(
    columns, exposures, transport: str, settings, spec: PropellerSpec, rated_torque_n_m: float, wake=None
) -> tuple[dict, dict, dict]:
    """Which cusps reach a propeller: per cusp `reaches_propeller`, `propeller_index` (−1: none or not
    modelled) and `arrival_time_s`, the summary's "transport" entry and the transports of the modelled
    runs (`transport_of_runs`, on discs of `spec`'s radius). Runs with an explicit fraction reaching (an
    override) and `transport="all"` load every cusp; otherwise the transport model decides (the flow
    transport at the wake fraction `wake`, None: Holtrop's)."""
    n = columns["run_id"].size
    runs = sorted(set(columns["run_id"].tolist()))
    override = {
        r: e.basis.fraction_reaching for r, e in exposures.items() if e.basis.fraction_reaching is not None
    }
    modelled = [] if transport == "all" else [r for r in runs if r not in override]
    out = {
        "reaches_propeller": np.ones(n, dtype=bool),
        "propeller_index": np.full(n, -1, dtype=np.int64),
        "arrival_time_s": np.full(n, math.nan),
    }
    settings = settings or TransportSettings()
    points = {}
    if transport == "flow":  # the cusps followed under the hull (floebreak.propeller.flow_transport)
        transports, points = flow_of_runs(
            columns, exposures, modelled, settings, spec, rated_torque_n_m, wake_fraction=wake
        )
    else:
        transports = transport_of_runs(columns, exposures, modelled, settings, spec.radius_m)
    for idx, t in transports.values():
        out["reaches_propeller"][idx] = t.propeller_index >= 0
        out["propeller_index"][idx] = t.propeller_index
        out["arrival_time_s"][idx] = t.arrival_time_s
    rule = "override" if override else transport
    summary: dict[str, Any] = {"rule": rule, "fraction_overrides": override, "settings": settings.as_dict()}
    if points:
        summary["operating_points"] = points
    if modelled:
        summary.update(transport_summary(transports, n))
    else:
        fraction = next(iter(override.values())) if len(set(override.values())) == 1 else None
        summary["fraction_reaching"] = 1.0 if not override else fraction
    summary["by_run"] = {
        r: override.get(r, float(np.mean(out["reaches_propeller"][columns["run_id"] == r]))) for r in runs
    }
    return out, summary, transports


def _check_spec(propeller) -> None:
    if not isinstance(propeller, PropellerSpec):
        raise InputError("propeller", f"{type(propeller).__name__} is not a PropellerSpec")


def _checked_arrangement_wake_draws(
    rule_arrangement, wake_fraction, spread_draws
) -> tuple[RuleArrangement, int]:
    """The rule's arrangement (default the Agulhas II's) and the spread's draws per run, after checking them
    and the wake fraction."""
    arrangement = RuleArrangement() if rule_arrangement is None else rule_arrangement
    if not isinstance(arrangement, RuleArrangement):
        raise InputError("rule_arrangement", f"{type(arrangement).__name__} is not a RuleArrangement")
    if wake_fraction is not None:
        require_range(
            "wake_fraction", wake_fraction, low=0.0, high=1.0, low_inclusive=True, high_inclusive=False
        )
    return arrangement, check_draws(spread_draws)


def _check_options(
    interpolation, beyond, volume_basis, cusp_speed_m_s, force_bin_kn, torque_bin_knm, weibull
):
    check_options(interpolation, beyond)
    if volume_basis not in VOLUME_BASES:
        raise InputError("volume_basis", f"unknown value {volume_basis!r}", allowed=", ".join(VOLUME_BASES))
    require_range("cusp_speed_m_s", cusp_speed_m_s, low=0.0, low_inclusive=True, unit="m/s")
    require_range("force_bin_kn", force_bin_kn, low=0.0, unit="kN")
    require_range("torque_bin_knm", torque_bin_knm, low=0.0, unit="kN m")
    if weibull not in WEIBULL_SHAPE:
        raise InputError("weibull", f"unknown propeller type {weibull!r}", allowed=", ".join(WEIBULL_SHAPE))


def _unload_missed(loads: dict, pitches) -> None:
    """Cusps that reach no propeller carry no load: their force and torque become NaN (in place)."""
    for pitch in pitches:
        for column in ("force_n", "torque_nm"):
            loads[f"{column}_{pitch_label(pitch)}"][~loads["reaches_propeller"]] = math.nan


def analyse_cusp_loads(
    cusps,
    *,
    load_model: str = "milling",
    transport: str = "flow",
    fem_tables=None,
    measured: TorqueSeries | None = None,
    polar_class: str | None = None,
    propeller: PropellerSpec = PropellerSpec(),  # noqa: B008 - frozen dataclass, immutable default
    rated_torque_n_m: float | None = None,
    interpolation: str = "newton",
    beyond: str = "power_law",
    volume_basis: str = DEFAULT_VOLUME_BASIS,
    volume_class_edges_m3=DEFAULT_CLASS_EDGES_M3,
    cusp_speed_m_s: float = 3.0,
    force_bin_kn: float = 10.0,
    torque_bin_knm: float = 10.0,
    weibull: str = "open",
    exposures: dict[str, RunExposure] | None = None,
    operating_profile: OperatingProfile | None = None,
    sn_curve: BasquinCurve | None = None,
    rule_arrangement: RuleArrangement | None = None,
    transport_settings: TransportSettings | None = None,
    progress: Callable[[str, int, int], None] | None = None,
    wake_fraction: float | None = None,
    spread_draws: int = SPREAD_DRAWS,
) -> PropellerResult:
    """The propeller analysis of `cusps` (dict of arrays or pyarrow.Table, `cusp_columns`), pure. `load_model`
    "milling" | "fem" (needs `fem_tables`: FemTables or {pitch: FemTable}; given tables take precedence),
    `transport` "flow" | "hull" (both with `transport_settings`) | "all"; an exposure's fraction reaching
    overrides the transport; `exposures` add rates, exceedance and rule-form fits; `measured` is
    compared; `rated_torque_n_m` (default: the Agulhas II line's) sets a warning; `rule_arrangement`: the
    rule's N_ice factors (`ruleform.rule_load_count`); `wake_fraction`: the flow transport's w (None:
    Holtrop's); `spread_draws`: samples per run (`propeller.spread`); `progress`: told of each stage."""
    columns = cusp_columns(cusps)
    _check_spec(propeller)
    _check_options(interpolation, beyond, volume_basis, cusp_speed_m_s, force_bin_kn, torque_bin_knm, weibull)
    load_model, tables, pitches = _load_tables(load_model, fem_tables, propeller, measured)
    check_choice("transport", transport, TRANSPORTS)
    rated = drive_rated_torque_n_m(propeller, rated_torque_n_m)
    arrangement, n_draws = _checked_arrangement_wake_draws(rule_arrangement, wake_fraction, spread_draws)
    edges_m3 = check_class_edges(volume_class_edges_m3)
    rule = ur_i3_loads(propeller, check_polar_class(polar_class)) if polar_class is not None else None
    exposures = check_exposures(exposures, set(columns["run_id"].tolist())) if exposures is not None else {}
    options = {
        **dict(load_model=load_model, transport=transport, pitches=list(pitches), rated_torque_n_m=rated),
        **dict(interpolation=interpolation, beyond=beyond, volume_basis=volume_basis),
        **dict(volume_class_edges_m3=edges_m3, cusp_speed_m_s=cusp_speed_m_s),
        **dict(density_threshold_per_knm=DENSITY_THRESHOLD_PER_KNM, polar_class=polar_class),
        **dict(weibull=weibull, rule_arrangement=dict(arrangement.__dict__), wake_fraction=wake_fraction),
    }
    order = transit_order(columns)
    columns = {k: v[order] for k, v in columns.items()}
    speed = np.array([_speed(exposures, r) for r in columns["run_id"].tolist()])
    reach_args = (exposures, transport, transport_settings, propeller, rated, wake_fraction)
    reaching, reach_info, transports = _reaching(columns, *reach_args)
    _report(progress, "transport")
    loads, placement = _placed_loads(columns, tables, options, propeller, speed, transports)
    loads.update(reaching)
    _unload_missed(loads, pitches)
    _report(progress, "per-cusp loads")
    ds = load_spectra(loads, dict.fromkeys(pitches), force_bin_kn, torque_bin_knm)
    options["force_bin_kn"] = ds.attrs["force_bin_width_kn"]  # as used: wider for far loads
    options["torque_bin_knm"] = ds.attrs["torque_bin_width_knm"]
    exceedance = {}
    if exposures:
        ds, exceedance = _add_rates(ds, loads, exposures)
    table_info = _table_info(loads, tables, pitches, rule)
    spectrum = _measured_spectrum(measured, torque_bin_knm) if measured is not None else None
    classes = _class_tables(loads, edges_m3)
    _report(progress, "spectra and rates")
    result = PropellerResult(
        options, propeller, tables, loads, classes, ds, exceedance, {}, rule, spectrum, exposures
    )
    result.summary.update(build_summary(result, table_info, operating_profile, sn_curve))
    _complete_summary(result.summary, reach_info, table_info, rated, rule, placement)
    spread_args = (exposures, transport, transport_settings, rated, speed, n_draws, wake_fraction)
    result.summary.update(_spread(result, columns, transports, *spread_args))
    _report(progress, "summary")
    return result


def _spread(
    result, columns, transports, exposures, transport, settings, rated, speed, n_draws, wake_fraction=None
) -> dict:
    """{"spread": …} (`spread.load_spread`; {} without transported runs): each transported run's own draw
    and, for the flow transport, `n_draws − 1` more; the per-cusp loads of a draw from the analysis' load
    model on that draw's engaged intervals."""
    if not transports:
        return {}
    spec, options = result.propeller, result.options
    settings = settings or TransportSettings()
    extra = {}
    if transport == "flow":
        runs = list(transports)
        extra = flow_draws_of_runs(
            columns, exposures, runs, settings, spec, rated, n_draws - 1, wake_fraction=wake_fraction
        )
    samples = {run: [transports[run], *extra.get(run, [])] for run in transports}
    model = get_load_model(options["load_model"])

    def loads_of(run, rows, moved):
        local = np.arange(rows.size)
        engaged = engaged_intervals({run: (local, moved)}, rows.size, spec) if model.places_on_blade else None
        sub = {k: v[rows] for k, v in columns.items()}
        loads = model.cusp_loads(sub, result.tables, options, spec, speed[rows], engaged)
        missed = moved.propeller_index < 0
        out = {}
        for pitch in options["pitches"]:
            f, q = (
                np.where(missed, math.nan, loads[f"{c}_{pitch_label(pitch)}"])
                for c in ("force_n", "torque_nm")
            )
            out[pitch] = (f, q)
        return out

    hours = {run: exposures[run].hours for run in transports if run in exposures}
    profile = (result.summary.get("rule_form") or {}).get("operating_profile") or {}
    spread = load_spread(
        samples,
        hours=hours,
        pitches=options["pitches"],
        loads_of=loads_of,
        profile_hours=profile.get("hours"),
    )
    spread["transport"] = transport
    return {"spread": spread}


# the steps of `analyse_cusp_loads` that its `progress` callback is told of, in order
ANALYSIS_STAGES = ("transport", "per-cusp loads", "spectra and rates", "summary")


def _report(progress: Callable[[str, int, int], None] | None, stage: str) -> None:
    if progress is not None:
        progress(stage, ANALYSIS_STAGES.index(stage) + 1, len(ANALYSIS_STAGES))


def _load_tables(load_model, fem_tables, propeller, measured) -> tuple[str, dict[float, FemTable], tuple]:
    """The load model (FEM when tables are given), its tables {pitch: FemTable} (none for the milling
    model) and pitches; InputError for FEM without tables and a `measured` that is not a TorqueSeries."""
    if measured is not None and not isinstance(measured, TorqueSeries):
        raise InputError(
            "measured", f"{type(measured).__name__} is not a TorqueSeries", allowed="a TorqueSeries"
        )
    # given tables select the FEM tables' model
    load_model = (
        "fem" if fem_tables is not None else check_choice("load_model", load_model, load_model_names())
    )
    model = get_load_model(load_model)
    if not model.needs_tables:
        return load_model, {}, model.pitches(propeller, {})
    if fem_tables is None:
        raise InputError(
            "fem_tables", "the FEM load model needs tables", allowed="FemTables, e.g. shipped_fem_tables()"
        )
    tables = fem_table_dict(fem_tables)
    return load_model, tables, model.pitches(propeller, tables)


def _speed(exposures: dict[str, RunExposure], run: str) -> float:
    return exposures[run].basis.speed_m_s if run in exposures else RateBasis().speed_m_s


def _complete_summary(summary, transport_info, table_info, rated, rule, placement=None) -> None:
    """The load model (with the milling model's placement on the blade), the transport (fractions
    reaching) and the out-of-range warnings."""
    options = summary["options"]
    summary["load_model"] = {
        "name": options["load_model"],
        "description": get_load_model(options["load_model"]).description,
        "rated_torque_knm": rated / 1e3,
    }
    if placement is not None:
        summary["load_model"]["placement"] = placement
    summary["transport"] = transport_info
    rates = summary.get("rates")
    for run, entry in ((rates or {}).get("per_run") or {}).items():
        entry["fraction_reaching"] = transport_info["by_run"].get(run, 0.0)
        entry["fraction_source"] = (
            "override" if run in transport_info["fraction_overrides"] else (transport_info["rule"])
        )
    warnings = summary["warnings"]
    if transport_info["fraction_overrides"]:
        warnings.append(override_warning(transport_info["fraction_overrides"]))
    warnings += torque_warnings(table_info, rated, None if rule is None else rule.max_torque_nm)
    if rule is not None:
        warnings += force_warnings(table_info, rule.backward_force_n, rule.forward_force_n)
    warnings += extrapolation_warnings(summary.get("rule_form"))
    absent = no_load_warning(summary.get("n_cusps", 0), transport_info)
    if absent is not None:
        warnings.insert(0, absent)
        summary["no_load_reason"] = no_load_reason(summary.get("n_cusps", 0), transport_info)
