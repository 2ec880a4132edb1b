"""Results of a voyage: per-period table, time-weighted load and torque spectra, rates, figures.

Pooling (docs/studies.md, "Voyages"). Period p lasts T_p hours and sails D_p = v_p T_p; n_p of its fields
completed, each L_p long. One simulated cusp of p stands for

    w_p = D_p / (n_p L_p)

cusps of the voyage, so the voyage's expected number of loads in a bin is C_b = Σ_p w_p · c_p,b (c_p,b: the
period's simulated cusps in the bin). Since the period's rate per hour is r_p,b = c_p,b v_p / (n_p L_p),
C_b = Σ_p T_p r_p,b: the time-weighted sum of the periods' rates. Rates per hour divide by Σ T_p (hours in
ice: the periods, not the gaps between them), per km by Σ D_p; the density is C_b / (Σ_b C_b · bin width).
Loads are per propeller: c_p,b counts each simulated cusp with its loads on one propeller (1 / n for a cusp
that reaches one, 0 for one that does not; f / n for every cusp with a fraction override f).

Loads per cusp and which cusps reach come from the propeller analysis of `floebreak propeller`
(`floebreak.app.propeller.analyse_runs` on the voyage's complete runs): the runs' profile picks the load
model and the transport (default: blade milling model and flow transport; thesis: FEM tables, every cusp),
for each pitch of the load model and "operated": each period at the pitch nearest its logged pitch (the
propeller's default pitch when the log has none). The logged rpm is recorded only. The propeller options
(`VoyageAnalysis`: polar class, fraction reaching, propellers, transport settings, shaft line) shape the
results only.

`write_voyage_results(voyage_dir)` re-builds ``results/`` (written atomically) from the runs on disk.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from floebreak.errors import InputError
from floebreak.io.jsonable import jsonable
from floebreak.io.writers import rows_to_columns, write_csv, write_json
from floebreak.propeller.spectra import pitch_label

RESULTS_DIR = "results"
BEYOND_TABLE_WARNING = 0.10  # share of a period's cusps beyond the FEM table that is worth a warning
QUANTITIES = {"force": ("kn", 10.0), "torque": ("knm", 10.0)}  # quantity → (unit in names, bin width)

FIELD_MARGIN_M = 5.0  # each side beyond the largest floe diameter (`studies.voyage` sizes the fields)


def period_weight(distance_m: float, simulated_length_m: float, n_fields_complete: int) -> float:
    """w_p = D_p / (n_p L_p): voyage cusps one simulated cusp of the period stands for (0 without runs)."""
    if n_fields_complete <= 0:
        return 0.0
    return distance_m / (n_fields_complete * simulated_length_m)


def weighted_counts(values: np.ndarray, weights: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Σ of the weights of the finite values in each bin [edges[i], edges[i+1]) (last bin closed)."""
    values, weights = np.asarray(values, dtype=float), np.asarray(weights, dtype=float)
    keep = np.isfinite(values)
    counts, _ = np.histogram(values[keep], bins=edges, weights=weights[keep])
    return counts


def read_voyage(voyage_dir: Path) -> dict[str, Any]:
    path = voyage_dir / "voyage.json"
    if not path.exists():
        raise InputError(
            "voyage_dir", f"{str(voyage_dir)!r} has no voyage.json", allowed="a voyage directory"
        )
    document = json.loads(path.read_text(encoding="utf-8"))
    if "periods" not in document:
        raise InputError("voyage_dir", f"{str(voyage_dir)!r} was never planned", allowed="a voyage directory")
    return document


def _run_summaries(voyage_dir: Path, names: set[str]) -> dict[str, dict]:
    """summary.json of the complete runs among `names`."""
    summaries = {}
    for name in sorted(names):
        path = voyage_dir / "runs" / name / "summary.json"
        if path.exists():
            summaries[name] = json.loads(path.read_text(encoding="utf-8"))
    return summaries


@dataclass(frozen=True)
class VoyageAnalysis:
    """The options of a voyage's propeller (and shaft) analysis, as on `floebreak propeller`: they shape
    ``results/`` only, so a voyage re-run with other values resumes its runs and re-writes its results.
    `transport`: `propeller.transport.TRANSPORT_KEYS` → value."""

    polar_class: str | None = None
    fraction_reaching: float | None = None
    n_propellers: int | None = None
    shaft_line: str | None = None
    transport: dict[str, Any] = field(default_factory=dict)

    def checked(self) -> VoyageAnalysis:
        """Validate every option (InputError naming the key, value and allowed range); return self."""
        from floebreak.propeller.iceclass import check_polar_class
        from floebreak.propeller.rates import RateBasis
        from floebreak.propeller.transport import transport_settings

        if self.polar_class is not None:
            check_polar_class(self.polar_class)
        overrides = {"fraction_reaching": self.fraction_reaching, "n_propellers": self.n_propellers}
        RateBasis(**{k: v for k, v in overrides.items() if v is not None})
        transport_settings(self.transport)
        if self.shaft_line is not None:
            from floebreak.app.inputs import load_shaft_line

            load_shaft_line(self.shaft_line)
        return self

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def voyage_propeller(voyage_dir: Path, names: list[str], analysis: VoyageAnalysis):
    """The propeller analysis (`floebreak.app.propeller.analyse_runs`) of the complete runs `names`, with
    the load model and transport of their profile, as `floebreak propeller` does; None without runs."""
    from floebreak.app.propeller import analyse_runs, read_run_dirs
    from floebreak.propeller.transport import transport_settings

    if not names:
        return None
    inputs = read_run_dirs(
        [voyage_dir / "runs" / name for name in names],
        pool=True,  # the periods differ in ice, field and speed by design
        fraction_reaching=analysis.fraction_reaching,
        n_propellers=analysis.n_propellers,
    )
    return analyse_runs(
        inputs, polar_class=analysis.polar_class, transport_settings=transport_settings(analysis.transport)
    )


def _nearest_pitch(pitches: list[float], pitch: float) -> float:
    return min(pitches, key=lambda p: (abs(p - pitch), p))


def period_loads(periods: list[dict], loads: dict[str, np.ndarray] | None, pitches, default_pitch) -> dict:
    """Per cusp of every period (a run shared by two periods counts in each): period index, load magnitudes
    [kN, kN·m] per case (each pitch "p<pitch>" of the load model, and "operated": each period at the pitch
    nearest its logged one, `default_pitch` without), `share` (loads on one propeller per cusp: 0 for a cusp
    that reaches none) and `reaches`. `loads`: the per-cusp table of `analyse_propeller` (None: no runs)."""
    pitches = sorted(float(p) for p in pitches)
    run_id = np.zeros(0, dtype=object) if loads is None else loads["run_id"]
    index = [np.flatnonzero(np.isin(run_id, period["runs"])) for period in periods]
    rows = np.concatenate(index) if index else np.zeros(0, dtype=int)
    period_of = np.concatenate([np.full(i.size, p["index"]) for i, p in zip(index, periods, strict=True)])
    operated = [
        _nearest_pitch(pitches, default_pitch if p[key] is None else p[key])
        for p, key in ((p, "propeller_pitch_percent") for p in periods)
    ]

    def column(key: str, empty) -> np.ndarray:
        return np.zeros(0, dtype=empty) if loads is None else loads[key][rows]

    cases: dict[str, dict[str, np.ndarray]] = {}
    for pitch in pitches:
        label = pitch_label(pitch)
        cases[label] = {
            "force": np.abs(column(f"force_n_{label}", float)) / 1e3,
            "torque": np.abs(column(f"torque_nm_{label}", float)) / 1e3,
            "beyond_table": column(f"beyond_table_{label}", bool),
        }
    pick = np.asarray([operated[p] for p in period_of], dtype=float)
    chosen = {key: np.full(pick.size, np.nan) for key in ("force", "torque")}
    chosen["beyond_table"] = np.zeros(pick.size, dtype=bool)
    for pitch in pitches:
        mask = pick == pitch
        for key, values in chosen.items():
            values[mask] = cases[pitch_label(pitch)][key][mask]
    cases["operated"] = chosen
    return {
        "period": period_of,
        "pitches": pitches,
        "operated_pitch": operated,
        "cases": cases,
        "volume_m3": column("volume_m3", float),
        "reaches": column("reaches_propeller", bool),
        "share": column("loads_per_propeller", float),
    }


def period_table(periods: list[dict], summaries: dict[str, dict], loads: dict[str, Any]) -> list[dict]:
    """One row per period: conditions, distance, fields, rates per km and per hour, mean cusp volume,
    operated torque statistics and the share of cusps beyond the FEM table."""
    rows = []
    operated = loads["cases"]["operated"]
    for period in periods:
        complete = [summaries[n] for n in period["runs"] if n in summaries]
        n = len(complete)
        simulated_km = n * period["simulated_length_m"] / 1e3
        km_per_h = period["speed_m_s"] * 3.6
        cusps = sum(s["n_cusps"] for s in complete)
        flips = sum(s["n_flipped"] for s in complete)
        mine = loads["period"] == period["index"]
        torque = operated["torque"][mine]
        torque = torque[np.isfinite(torque)]  # cusps that reach no propeller carry no load
        per_km = cusps / simulated_km if n else math.nan
        rows.append(
            {
                **{k: period[k] for k in ("index", "row", "label", "start_utc", "end_utc", "duration_h")},
                "concentration_percent": 100.0 * period["concentration"],
                "mean_thickness_m": period["mean_thickness_m"],
                "diameter_classes": " ".join(
                    f"{d:g}m:{p:g}%"
                    for d, p in zip(period["diameter_classes_m"], period["percentages"], strict=True)
                ),
                **{k: period[k] for k in ("speed_m_s", "speed_source", "distance_m", "simulated_length_m")},
                "field_width_m": period["field_width_m"],
                "generator": period["generator"],
                "n_fields_complete": n,
                "n_fields_planned": len(period["runs"]),
                "weight": period_weight(period["distance_m"], period["simulated_length_m"], n),
                "n_cusps_simulated": cusps,
                "cusps_per_km": per_km,
                "cusps_per_hour": per_km * km_per_h,
                "cusps_in_period": per_km * period["distance_m"] / 1e3,
                "flips_per_km": flips / simulated_km if n else math.nan,
                "flips_per_hour": flips / simulated_km * km_per_h if n else math.nan,
                "mean_cusp_volume_m3": float(np.mean(loads["volume_m3"][mine])) if mine.any() else math.nan,
                "operated_pitch_percent": loads["operated_pitch"][period["index"]],
                "propeller_rpm": period["propeller_rpm"],
                "mean_torque_knm": float(np.mean(torque)) if torque.size else math.nan,
                "max_torque_knm": float(np.max(torque)) if torque.size else math.nan,
                "beyond_table_fraction": float(np.mean(operated["beyond_table"][mine]))
                if mine.any()
                else math.nan,
                "fraction_reaching": float(np.mean(loads["reaches"][mine])) if mine.any() else math.nan,
                # loads on one propeller per hour: Σ share / (n L) × v
                "loads_per_hour": float(np.sum(loads["share"][mine])) / simulated_km * km_per_h
                if n
                else math.nan,
            }
        )
    return rows


def cusp_weights(loads: dict[str, Any], rows: list[dict], share: float = 1.0) -> np.ndarray:
    """Loads on one propeller each simulated cusp stands for: its period's weight w_p × its own share
    (`loads["share"]`: f / n, or 1 / n for a cusp that reaches a propeller and 0 for one that does not)
    × `share`."""
    weight_of = np.asarray([row["weight"] for row in rows], dtype=float)
    if not loads["period"].size:
        return np.zeros(0)
    return share * weight_of[loads["period"]] * loads.get("share", 1.0)


def voyage_rule_form(
    loads: dict[str, Any], weights: np.ndarray, per_hour: float | None, profile=None, rule=None
) -> dict[str, Any]:
    """Rule-form fit (notes §7.3) of the pooled "operated" |F| [kN] and |Q| [kN·m], each cusp weighted by
    the loads it stands for (`cusp_weights`; weighted maximum likelihood, intervals from the effective
    sample size, `fit_rule_form`); x_max per hour at `per_hour` loads and over the operating `profile`
    (an `OperatingProfile` or None). Rule shape: open propeller (the Agulhas II's, thesis §6.1). `rule`:
    {"force_kn": F_b, "torque_knm": Q_max, "n_ice": N_ice} of a polar class, or None."""
    from floebreak.propeller.iceclass import WEIBULL_SHAPE
    from floebreak.propeller.summary import rule_form_entry

    operated = loads["cases"]["operated"]
    out: dict[str, Any] = {
        "form": "P(X >= x) = exp(-(x/x_max)^k ln N) (notes §7.3, as recalled, verify against the rule text)",
        "case": "operated",
        "weights": "period weight D/(n L) × loads per cusp on one propeller (1/n reaching, 0 not; f/n "
        "with a fraction override)",
        "rule_n_ice": None if rule is None else rule["n_ice"],
        "n_ice_per_hour": per_hour,
        "operating_profile": None
        if profile is None
        else {"hours_in_ice_per_year": profile.hours_in_ice_per_year, "years": profile.years},
    }
    for quantity, key in (("force", "force_kn"), ("torque", "torque_knm")):
        rule_max, rule_n = (None, None) if rule is None else (rule[key], rule["n_ice"])
        out[key] = rule_form_entry(
            operated[quantity],
            1.0,
            per_hour,
            profile,
            rule_max,
            rule_n,
            WEIBULL_SHAPE["open"],
            weights=weights,
        )
    return out


def pooled_spectra(loads: dict[str, Any], rows: list[dict], share: float = 1.0) -> dict[str, Any]:
    """Per case and quantity: bin edges, the voyage's expected counts, per hour, per km, density, and the
    exceedances of each lower bin edge — the time-weighted pooling of the module docstring. `share`: loads
    on one propeller per cusp (fraction reaching / number of propellers)."""
    from floebreak.propeller.rates import weighted_exceedance
    from floebreak.propeller.spectra import bin_edges, fitting_width

    weights = cusp_weights(loads, rows, share)
    simulated = [row for row in rows if row["n_fields_complete"]]  # a period without runs has no loads
    hours = sum(row["duration_h"] for row in simulated)
    km = sum(row["distance_m"] for row in simulated) / 1e3
    out: dict[str, Any] = {"hours": hours, "distance_km": km}
    for quantity, (_, width) in QUANTITIES.items():
        every = np.concatenate([case[quantity] for case in loads["cases"].values()])
        width = fitting_width(every, width)
        edges = bin_edges(every[np.isfinite(every)], width, start=0.0)
        for case, values in loads["cases"].items():
            counts = weighted_counts(values[quantity], weights, edges)
            total = counts.sum()
            out[(case, quantity)] = {
                "edges": edges,
                "width": width,
                "count": counts,
                "per_hour": counts / hours if hours else np.full(counts.size, np.nan),
                "per_km": counts / km if km else np.full(counts.size, np.nan),
                "density": counts / (total * width) if total > 0 else np.full(counts.size, np.nan),
                "exceedances": weighted_exceedance(values[quantity], weights, edges[:-1]),  # at lower edges
                "total": float(total),
            }
    return out


PERIOD_COLUMNS_MD = (  # (key, header, format) of periods.md
    ("index", "#", "d"),
    ("start_utc", "start (UTC)", "s"),
    ("duration_h", "T [h]", ".3g"),
    ("concentration_percent", "c [%]", "g"),
    ("mean_thickness_m", "h [m]", "g"),
    ("diameter_classes", "diameter classes", "s"),
    ("speed_m_s", "v [m/s]", "g"),
    ("distance_m", "D [m]", ".0f"),
    ("simulated_length_m", "L [m]", ".0f"),
    ("field_width_m", "W [m]", ".1f"),
    ("generator", "generator", "s"),
    ("n_fields_complete", "fields", "d"),
    ("cusps_per_km", "cusps/km", ".1f"),
    ("cusps_per_hour", "cusps/h", ".0f"),
    ("flips_per_km", "flips/km", ".1f"),
    ("mean_cusp_volume_m3", "V̄_cusp [m³]", ".3g"),
    ("fraction_reaching", "reaching", ".0%"),
    ("loads_per_hour", "loads/h per propeller", ".0f"),
    ("mean_torque_knm", "mean abs Q [kN·m]", ".0f"),
    ("beyond_table_fraction", "beyond FEM table", ".0%"),
)


def _cell(value: Any, fmt: str = "g") -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return ""
    if isinstance(value, float | int) and not isinstance(value, bool):
        return format(value, fmt if fmt != "s" else "g")
    return str(value)


def _periods_markdown(rows: list[dict], notes: list[str]) -> str:
    lines = ["# Voyage periods", "", *[f"- {note}" for note in notes], ""]
    lines.append("| " + " | ".join(h for _, h, _ in PERIOD_COLUMNS_MD) + " |")
    lines.append("|" + "---|" * len(PERIOD_COLUMNS_MD))
    for row in rows:
        lines.append("| " + " | ".join(_cell(row[k], f) for k, _, f in PERIOD_COLUMNS_MD) + " |")
    return "\n".join(lines) + "\n"


def _spectra_rows(spectra: dict[str, Any]) -> tuple[list[dict], list[dict]]:
    """Long tables of the pooled spectra and exceedances (one row per case, quantity and bin)."""
    spectrum_rows, exceedance_rows = [], []
    for key, data in spectra.items():
        if not isinstance(key, tuple):
            continue
        case, quantity = key
        unit = QUANTITIES[quantity][0]
        edges = data["edges"]
        for i in range(edges.size - 1):
            spectrum_rows.append(
                {
                    "case": case,
                    "quantity": quantity,
                    f"bin_lower_{unit}": edges[i],
                    f"bin_upper_{unit}": edges[i + 1],
                    "count_voyage": data["count"][i],
                    "per_hour": data["per_hour"][i],
                    "per_km": data["per_km"][i],
                    f"density_per_{unit}": data["density"][i],
                }
            )
            exceedance_rows.append(
                {
                    "case": case,
                    "quantity": quantity,
                    f"level_{unit}": edges[i],
                    "exceedances_voyage": data["exceedances"][i],
                    "per_hour": data["exceedances"][i] / spectra["hours"] if spectra["hours"] else math.nan,
                    "per_km": data["exceedances"][i] / spectra["distance_km"]
                    if spectra["distance_km"]
                    else math.nan,
                }
            )
    return spectrum_rows, exceedance_rows


def _split_by_quantity(rows: list[dict]) -> dict[str, list[dict]]:
    out: dict[str, list[dict]] = {}
    for row in rows:
        out.setdefault(row["quantity"], []).append(row)
    return out


def _case_summary(spectra: dict[str, Any], loads: dict[str, Any]) -> dict[str, Any]:
    """Per case: loads on one propeller per hour and per km, largest load, share of cusps beyond the FEM
    table."""
    out = {}
    for case, values in loads["cases"].items():
        torque = spectra[(case, "torque")]
        force = values["force"][np.isfinite(values["force"])]
        q = values["torque"][np.isfinite(values["torque"])]
        out[case] = {
            "loads_voyage": torque["total"],
            "loads_per_hour": torque["total"] / spectra["hours"] if spectra["hours"] else None,
            "loads_per_km": torque["total"] / spectra["distance_km"] if spectra["distance_km"] else None,
            "max_force_kn": float(force.max()) if force.size else None,
            "max_torque_knm": float(q.max()) if q.size else None,
            "beyond_table_fraction": float(np.mean(values["beyond_table"]))
            if values["beyond_table"].size
            else None,
            "force_bin_width_kn": spectra[(case, "force")]["width"],
            "torque_bin_width_knm": torque["width"],
        }
    return out


def _placement_text(model: dict[str, Any]) -> str:
    """Where the milling model places each cusp on the blade, in brackets after the model's name; empty
    for the FEM tables and without runs."""
    return f" ({model['placement']})" if model.get("placement") else ""


def voyage_notes(document: dict[str, Any], rows: list[dict], model: dict[str, Any]) -> list[str]:
    """What a reader of the tables must know: rules, scaling, load model, fallbacks, failures (`model`:
    `load_model_record`)."""
    reach = model["transport"]
    notes = [
        "counts are scaled by distance: each period's cusps × D / (fields × L); L = min(D, max_length_m = "
        f"{document['identity']['max_length_m']:g} m)",
        f"field width W = beam + 2 × largest floe diameter + 2 × {FIELD_MARGIN_M:g} m margin: the field's "
        "edges never touch the ship's band",
        f"per-cusp loads: {model['load_model']} model{_placement_text(model)}; fraction of cusps reaching a "
        "propeller "
        f"{_fraction_text(reach)} ({reach['rule']}: {TRANSPORT_TEXT[reach['rule']]}); loads are per "
        f"propeller ({model['n_propellers']} propellers); rates per hour are per hour in ice (the periods' "
        "hours, not the gaps between them)",
        "operated case: each period at the load model's pitch nearest its logged pitch; logged rpm recorded "
        f"only ({_rpm_text(model['load_model'])})",
    ]
    shares = [row["beyond_table_fraction"] for row in rows]
    beyond = max((share for share in shares if math.isfinite(share)), default=0.0)
    if beyond > BEYOND_TABLE_WARNING:
        notes.append(
            f"warning: in a period up to {beyond:.0%} of the cusps lie beyond the largest FEM cusp; their "
            f"loads follow the beyond-table policy {model['options']['beyond']!r} (docs/propeller.md)"
        )
    for row in rows:
        if row["generator"] != "circles":
            notes.append(f"period {row['index']} ({row['start_utc']}): {row['generator']} fields")
        if row["n_fields_complete"] < row["n_fields_planned"]:
            notes.append(
                f"period {row['index']}: {row['n_fields_complete']} of {row['n_fields_planned']} fields "
                "complete (see failed/)"
            )
    return notes


def _rpm_text(load_model: str) -> str:
    """How the load model's loads depend on the propeller's speed (`LoadModel.rpm_text`)."""
    from floebreak.propeller.loads import get_load_model, load_model_names

    return get_load_model(load_model).rpm_text if load_model in load_model_names() else "no runs"


TRANSPORT_TEXT = {
    "hull": "the kinematic transport model decides per cusp",
    "flow": "each cusp is followed under the hull to the propeller plane (buoyancy, friction, drag, suction)",
    "all": "every cusp reaches, thesis §6.2",
    "override": "--fraction-reaching / propeller.fraction_reaching, every cusp loads with that weight",
}


def _fraction_text(transport: dict[str, Any]) -> str:
    fraction = transport.get("fraction_reaching")
    return "–" if fraction is None else f"{fraction:.3g}"


def load_model_record(result, analysis: VoyageAnalysis) -> dict[str, Any]:
    """The load model, transport (fraction reaching), rule and options of the voyage's propeller analysis
    (`voyage_propeller`'s result, or None without runs: the defaults)."""
    from floebreak.propeller.rates import RateBasis
    from floebreak.propeller.ruleform import result_load_count
    from floebreak.propeller.spec import PropellerSpec

    n_propellers = analysis.n_propellers or RateBasis().n_propellers
    if result is None:
        return {
            "load_model": None,
            "placement": None,
            "transport": {"rule": "all" if analysis.fraction_reaching is None else "override"},
            "n_propellers": n_propellers,
            "options": {"beyond": None},
            "rule": None,
            "pitch_info": {},
            "rated_torque_knm": None,
            "default_pitch": PropellerSpec().pitch_percent,
        }
    summary = result.summary
    rule = None
    if result.rule is not None:
        rule = {
            **result.rule.as_dict(),
            "force_kn": result.rule.backward_force_n / 1e3,
            "torque_knm": result.rule.max_torque_nm / 1e3,
            "n_ice": result_load_count(result).n_ice_low,  # per blade, the lower k_1 of a wing propeller
        }
    per_run = {e.basis.n_propellers for e in result.exposures.values()}
    transport = {k: v for k, v in summary["transport"].items() if k != "by_run"}
    return {
        "load_model": summary["load_model"]["name"],
        "load_model_description": summary["load_model"]["description"],
        "placement": summary["load_model"].get("placement"),
        "transport": transport,
        "n_propellers": per_run.pop() if len(per_run) == 1 else n_propellers,
        "options": jsonable(result.options),
        "rule": rule,
        "pitch_info": summary["pitches"],
        "rated_torque_knm": summary["load_model"]["rated_torque_knm"],
        "default_pitch": result.propeller.pitch_percent,
    }


def voyage_warnings(model: dict[str, Any], rule_form: dict[str, Any]) -> list[str]:
    """The out-of-range warnings of `floebreak propeller` on the voyage: a fraction
    override, a per-cusp torque above 2 × the rated torque or the rule's Q_max, and a rule-form x_max more
    than 1.5 × beyond the largest fitted load."""
    from floebreak.propeller.load_models import extrapolation_warnings, override_warning, torque_warnings

    out = []
    overrides = model["transport"].get("fraction_overrides")
    if overrides:
        out.append(override_warning(overrides))
    if model["rated_torque_knm"] is not None:
        rule = model["rule"]
        q_max = None if rule is None else rule["max_torque_nm"]
        out += torque_warnings(model["pitch_info"], 1e3 * model["rated_torque_knm"], q_max)
    fits = {"poperated": {k: rule_form[k] for k in ("force_kn", "torque_knm")}}
    out += [w.replace("pitch operated %", "operated pitch") for w in extrapolation_warnings(fits)]
    return out


def _voyage_loads(voyage_dir: Path, periods: list[dict], names: list[str], analysis: VoyageAnalysis):
    """The voyage's propeller analysis (`voyage_propeller`), its per-period loads and its record."""
    result = voyage_propeller(voyage_dir, names, analysis)
    model = load_model_record(result, analysis)
    pitches = result.pitches if result is not None else (0.0, model["default_pitch"])
    loads = period_loads(periods, None if result is None else result.loads, pitches, model["default_pitch"])
    if not np.all(np.isfinite(loads["share"])):  # runs without a transit distance have no exposure
        fraction = 1.0 if analysis.fraction_reaching is None else analysis.fraction_reaching
        loads["share"] = np.where(loads["reaches"], fraction / model["n_propellers"], 0.0)
    return loads, model


def write_voyage_results(
    voyage_dir: str | Path, profile=None, analysis: VoyageAnalysis | None = None
) -> dict[str, Any]:
    """(Re)write ``results/`` of a voyage directory from its runs, atomically; returns the summary.
    `profile`: an `OperatingProfile` (hours in ice per year, years) for the rule-form extrapolation;
    `analysis`: the propeller options (default: those voyage.json records)."""
    from floebreak.io.atomic import atomic_directory
    from floebreak.io.provenance import provenance

    voyage_dir = Path(voyage_dir)
    document = read_voyage(voyage_dir)
    if analysis is None:
        analysis = VoyageAnalysis(**document.get("analysis", {}))
    periods = document["periods"]
    summaries = _run_summaries(voyage_dir, {n for p in periods for n in p["runs"]})
    loads, model = _voyage_loads(voyage_dir, periods, sorted(summaries), analysis.checked())
    rows = period_table(periods, summaries, loads)
    spectra = pooled_spectra(loads, rows)
    notes = voyage_notes(document, rows, model)
    summary = {
        "provenance": provenance(command="floebreak voyage", log=document["log"], **document["identity"]),
        "hours_in_ice": spectra["hours"],
        "distance_km": spectra["distance_km"],
        "n_periods": len(periods),
        "n_periods_simulated": sum(1 for row in rows if row["n_fields_complete"]),
        "n_runs_complete": len(summaries),
        "cusps_voyage": sum(row["cusps_in_period"] for row in rows if row["n_fields_complete"]),
        "pitches_percent": loads["pitches"],
        "analysis": analysis.as_dict(),
        "load_model": {k: model[k] for k in ("load_model", "placement", "rated_torque_knm") if k in model}
        | {"description": model.get("load_model_description")},
        "transport": model["transport"],
        "propeller_options": model["options"],
        "propeller": {
            "count": model["n_propellers"],
            "fraction_reaching": model["transport"].get("fraction_reaching"),
        },
        "ice_class": model["rule"],
        "cases": _case_summary(spectra, loads),
        "generators": {str(p["index"]): [p["generator"], p["generator_reason"]] for p in periods},
        "notes": notes,
    }
    summary["cusps_per_hour"] = summary["cusps_voyage"] / spectra["hours"] if spectra["hours"] else None
    weights = cusp_weights(loads, rows)
    summary["rule_form"] = voyage_rule_form(
        loads, weights, summary["cases"]["operated"]["loads_per_hour"], profile, model["rule"]
    )
    summary["warnings"] = voyage_warnings(model, summary["rule_form"])
    notes += [f"warning: {w}" for w in summary["warnings"]]
    if analysis.shaft_line is not None:
        from floebreak.studies.voyage_shaft import voyage_shaft

        shaft = voyage_shaft(voyage_dir, periods, rows, analysis.shaft_line, analysis.transport)
        summary["shaft"] = shaft.summary
    spectrum_rows, exceedance_rows = _spectra_rows(spectra)
    with atomic_directory(voyage_dir / RESULTS_DIR, overwrite=True, field="out") as temp:
        write_csv(temp / "periods.csv", rows_to_columns(rows), notes)
        markdown = _periods_markdown(rows, notes) + _rule_form_markdown(summary["rule_form"])
        (temp / "periods.md").write_text(markdown, encoding="utf-8")
        for name, table in (("spectra", spectrum_rows), ("exceedance", exceedance_rows)):
            for quantity, quantity_rows in _split_by_quantity(table).items():
                comment = f"voyage {name} of |{quantity}|, time-weighted over the periods; {notes[0]}"
                write_csv(temp / f"{name}_{quantity}.csv", rows_to_columns(quantity_rows), [comment])
        if analysis.shaft_line is not None:
            shaft.write(temp / "shaft")
        _figures(temp / "figures", rows, spectra, list(loads["cases"]))
        _rule_form_figure(temp / "figures", loads, weights, spectra)
        _write_report(temp, summary, rows, spectra, loads)
        summary["files"] = sorted(p.relative_to(temp).as_posix() for p in temp.rglob("*") if p.is_file())
        summary["files"].append("summary.json")
        write_json(temp / "summary.json", summary)
    return summary


def _figures(folder: Path, rows: list[dict], spectra: dict[str, Any], cases: list[str]) -> None:
    from floebreak.io.figures import save_figure
    from floebreak.plotting import voyage as figs

    folder.mkdir()
    for quantity in QUANTITIES:
        data = {case: spectra[(case, quantity)] for case in cases}
        save_figure(figs.plot_rate_spectrum(data, quantity), folder / f"{quantity}_spectrum.png")
    data = {(case, q): spectra[(case, q)] for case in cases for q in QUANTITIES}
    save_figure(figs.plot_exceedance(data, spectra["hours"]), folder / "exceedance.png")
    save_figure(figs.plot_timeline(rows), folder / "timeline.png")


RULE_FORM_COLUMNS = (
    "quantity",
    "fit k (95 % CI)",
    "rule k",
    "λ",
    "N_ice per hour",
    "x_max per hour (95 % CI)",
    "N over the profile",
    "x_max over the profile (95 % CI)",
)


def _interval_text(entry: dict, key: str, fmt: str) -> str:
    if key not in entry:
        return "–"
    low, high = entry[f"{key}_ci95"]
    return f"{entry[key]:{fmt}} ({low:{fmt}}–{high:{fmt}})"


def rule_form_rows(rule_form: dict[str, Any]) -> list[list[str]]:
    """Rows of `RULE_FORM_COLUMNS` (text) for the voyage's rule-form fit: periods.md and the terminal."""
    out = []
    for key, name in (("force_kn", "|F| [kN]"), ("torque_knm", "|Q| [kN·m]")):
        entry = rule_form[key]
        if "k" not in entry:
            out.append([name, f"no fit: {entry['reason']}", *["–"] * (len(RULE_FORM_COLUMNS) - 2)])
            continue
        out.append(
            [
                name,
                _interval_text(entry, "k", ".3f"),
                f"{entry['rule_k']:g}",
                f"{entry['scale']:.4g}",
                _cell(entry.get("n_per_hour"), ".4g") or "–",
                _interval_text(entry, "x_max_per_hour", ".0f"),
                _cell(entry.get("n_lifetime"), ".4g") or "–",
                _interval_text(entry, "x_max_lifetime", ".0f"),
            ]
        )
    return out


def _rule_form_markdown(rule_form: dict[str, Any]) -> str:
    profile = rule_form["operating_profile"]
    lines = [
        "",
        "# Rule-form fit of the operated loads",
        "",
        f"- {rule_form['form']}; weights: {rule_form['weights']}",
        "- 95 % intervals from the effective sample size (Σw)²/Σw² (docs/studies.md, Voyages)",
        "- operating profile: "
        + (
            "none (give --hours-in-ice-per-year and --years)"
            if profile is None
            else f"{profile['hours_in_ice_per_year']:g} h in ice per year × {profile['years']:g} years"
        ),
        "",
        "| " + " | ".join(RULE_FORM_COLUMNS) + " |",
        "|" + "---|" * len(RULE_FORM_COLUMNS),
    ]
    lines += [
        "| " + " | ".join(c.replace("|", "\\|") for c in row) + " |" for row in rule_form_rows(rule_form)
    ]
    return "\n".join(lines) + "\n"


def _rule_form_figure(folder: Path, loads: dict[str, Any], weights: np.ndarray, spectra: dict) -> None:
    from floebreak.io.figures import save_figure
    from floebreak.plotting.propeller import plot_rule_form

    torque = spectra[("operated", "torque")]
    table = {"level": torque["edges"][:-1], "per_hour": torque["exceedances"] / spectra["hours"]}
    figure = plot_rule_form(
        {"operated": loads["cases"]["operated"]["torque"] * 1e3},  # kN·m → N·m
        {"torque_operated": table} if spectra["hours"] else {},
        weights={"operated": weights},
    )
    save_figure(figure, folder / "rule_form.png")


VOYAGE_FIGURES = {
    "torque_spectrum.png": "Voyage |Q| loads per hour in ice per bin, time-weighted over the periods.",
    "force_spectrum.png": "Voyage |F| loads per hour in ice per bin, time-weighted over the periods.",
    "exceedance.png": "Exceedances per hour in ice on one propeller.",
    "rule_form.png": "Operated |Q|: weighted empirical exceedance, the fitted rule form "
    "exp(−(x/x_max)^k ln N) and the rule's shape through the same x_max; right: exceedances per hour on "
    "one propeller.",
    "timeline.png": "Ice conditions and load rates per period.",
}


def propeller_view(summary: dict[str, Any], rows: list[dict], loads: dict[str, Any]) -> dict[str, Any]:
    """The voyage's pooled loads in the shape of a propeller summary (warnings, rates, pitches per case,
    the rule form of "operated") for `floebreak.output.report.propeller_parts`."""
    operated = summary["cases"]["operated"]
    propeller = summary["propeller"]
    pitches = {}
    for case, values in loads["cases"].items():
        beyond = values["beyond_table"]
        top = summary["cases"][case]["max_torque_knm"]
        pitches[case] = {
            "pitch_percent": case if case == "operated" else float(case[1:]),
            "n_beyond_table": int(beyond.sum()),
            "fraction_beyond_table": float(beyond.mean()) if beyond.size else 0.0,
            "torque_range_knm": None if top is None else [0.0, top],
        }
    rates = None
    if summary["hours_in_ice"]:
        rates = {
            "transit_m": summary["distance_km"] * 1e3,
            "hours_in_ice": summary["hours_in_ice"],
            "per_run": {
                str(r["index"]): {
                    "speed_m_s": r["speed_m_s"],
                    "fraction_reaching": r["fraction_reaching"],
                    "n_propellers": propeller["count"],
                }
                for r in rows
                if r["n_fields_complete"]
            },
            "loads_per_hour_per_propeller": operated["loads_per_hour"],
            "loads_per_km_per_propeller": operated["loads_per_km"],
        }
    return {
        "warnings": [
            note.removeprefix("warning: ") for note in summary["notes"] if note.startswith("warning")
        ],
        "rates": rates,
        "pitches": pitches,
        "rule_form": {"operated": {"torque_knm": summary["rule_form"]["torque_knm"]}},
    }


def _write_report(temp: Path, summary: dict, rows: list[dict], spectra: dict, loads: dict) -> None:
    from floebreak.output.report import render_voyage_report

    title = f"floebreak voyage {summary['provenance'].get('log', '')}"
    view = propeller_view(summary, rows, loads)
    text = render_voyage_report(title, summary["notes"], jsonable(view), temp / "figures", VOYAGE_FIGURES)
    (temp / "report.html").write_text(text, encoding="utf-8")
