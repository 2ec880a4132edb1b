"""The JSON-ready summary of a propeller analysis: counts, ranges, rates, rule-form fits and warnings
(pure; `floebreak.propeller.pipeline.analyse_cusp_loads` builds it, `floebreak.output.propeller_files` writes
it)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from floebreak.errors import InputError
from floebreak.propeller.iceclass import WEIBULL_SHAPE
from floebreak.propeller.ruleform import (
    BasquinCurve,
    OperatingProfile,
    fit_rule_form,
    miner_damage,
    result_load_count,
)
from floebreak.propeller.spec import propeller_pitch_angle_deg
from floebreak.propeller.spectra import envelope, pitch_label, torque_ranges_above

BEYOND_WARNING_FRACTION = 0.10  # warn (terminal, summary, report) when more cusps lie beyond the FEM table
# A horizon beyond a million years (in hours) is "never": no ship, fleet or material record spans it, and
# the fitted tail says nothing that far out. Such horizons are null in the summary and "never" in text.
NEVER_HOURS = 1e6 * 8766.0


def finite_range(values) -> list[float] | None:
    """[min, max] of the finite values, None if there are none."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return [float(values.min()), float(values.max())] if values.size else None


def beyond_table_warnings(table_info: dict[str, dict], beyond: str) -> list[str]:
    """A warning per pitch where more than `BEYOND_WARNING_FRACTION` of the cusps lie beyond the table."""
    out = []
    for info in table_info.values():
        share = info["fraction_beyond_table"]
        if share > BEYOND_WARNING_FRACTION:
            out.append(
                f"pitch {info['pitch_percent']:g} %: {100 * share:.0f} % of the cusps "
                f"({info['n_beyond_table']}) lie beyond the FEM table (largest cusp "
                f"{info['max_volume_m3']:g} m³); their loads come from beyond = {beyond}"
            )
    return out


def _rates(result) -> dict[str, Any] | None:
    """Time base and cusp rates on one propeller (None without exposures)."""
    if not result.exposures:
        return None
    runs = sorted(result.exposures)
    hours = sum(result.exposures[r].hours for r in runs)
    km = sum(result.exposures[r].km for r in runs)
    loads = float(np.nansum(result.loads["loads_per_propeller"]))
    return {
        "transit_m": float(sum(result.exposures[r].transit_m for r in runs)),
        "hours_in_ice": hours,
        "per_run": {
            r: {"transit_m": e.transit_m, "hours_in_ice": e.hours, **e.basis.as_dict()}
            for r, e in result.exposures.items()
        },
        "loads_per_propeller": loads,
        "loads_per_hour_per_propeller": loads / hours if hours > 0 else None,
        "loads_per_km_per_propeller": loads / km if km > 0 else None,
        "note": "counts on one propeller: cusps × fraction_reaching / n_propellers, over the summed transit "
        "(fraction_reaching: the transport model's, every cusp's, or an override: fraction_source)",
    }


def rule_form_entry(
    amplitudes, unit_scale: float, per_hour: float | None, profile, rule_max, rule_n, shape_rule, weights=None
):
    """One quantity's rule-form fit in kN or kN·m: the fitted loads' [min, max] (`validity_range`), k with
    95 % interval, λ, x_max per hour and over the
    operating profile with 95 % intervals, and the hours until the rule maximum is expected once.
    `weights` (one per amplitude): a weighted fit (`fit_rule_form`), with its effective sample size."""
    try:
        fit = fit_rule_form(amplitudes, weights=weights)
    except InputError as error:
        return {"fit": None, "reason": str(error)}
    fitted = np.abs(np.asarray(amplitudes, dtype=float))
    fitted = fitted[np.isfinite(fitted) & (fitted > 0.0)]
    entry: dict[str, Any] = {
        "validity_range": [float(fitted.min()) / unit_scale, float(fitted.max()) / unit_scale],
        "k": fit.shape_k,
        "k_ci95": list(fit.shape_interval()),
        "rule_k": shape_rule,
        "scale": fit.scale / unit_scale,
        "n_samples": fit.n_samples,
    }
    if fit.n_effective is not None:
        entry["n_effective"] = fit.n_effective
    if per_hour is not None and per_hour > 1.0:
        entry["n_per_hour"] = per_hour
        entry["x_max_per_hour"] = fit.x_max(per_hour) / unit_scale
        entry["x_max_per_hour_ci95"] = [v / unit_scale for v in fit.x_max_interval(per_hour)]
    if per_hour is not None and profile is not None and per_hour * profile.hours > 1.0:
        n_life = per_hour * profile.hours
        entry["n_lifetime"] = n_life
        entry["x_max_lifetime"] = fit.x_max(n_life) / unit_scale
        entry["x_max_lifetime_ci95"] = [v / unit_scale for v in fit.x_max_interval(n_life)]
    if rule_max is not None:
        entry["rule_maximum"] = rule_max / unit_scale  # F_b (backward blade force) or Q_max
        entry.update(rule_maximum_horizon(rule_max, fit.scale, fit.shape_k, per_hour))
        if rule_n is not None:
            entry["x_max_at_rule_n_ice"] = fit.x_max(rule_n) / unit_scale
    return entry


def rule_maximum_horizon(rule_max: float, scale: float, shape_k: float, per_hour: float | None) -> dict:
    """Loads N* and hours until the rule maximum is expected once: x_max(N*) = rule_max, so
    ln N* = (rule_max / λ)^k (notes §7.3), and hours = N* / (loads per hour).

    Both are None (JSON null, "never" in text: `horizon_text`) where N* overflows a float or the hours
    exceed `NEVER_HOURS`; the hours are also None without a time base."""
    with np.errstate(over="ignore", divide="ignore"):  # numpy floats: an overflow gives inf, not an error
        log_n = float(np.float64(rule_max / scale) ** shape_k) if scale > 0.0 else math.inf
    n_star = math.exp(log_n) if log_n < math.log(np.finfo(float).max) else math.inf
    hours = n_star / per_hour if per_hour else None
    never = not math.isfinite(n_star) or (hours is not None and not hours <= NEVER_HOURS)
    return {
        "loads_until_rule_maximum": None if not math.isfinite(n_star) else n_star,
        "hours_until_rule_maximum": None if never else hours,
        "rule_maximum_never": bool(never),
    }


def horizon_text(hours: float | None, never: bool = False) -> str:
    """A horizon in hours for tables: "never" (`never`, or hours non-finite or beyond `NEVER_HOURS`),
    "–" without a time base (None), else three significant digits."""
    if never or (hours is not None and not (math.isfinite(hours) and hours <= NEVER_HOURS)):
        return "never"
    return "–" if hours is None else f"{hours:.3g} h"


def _rule_form(result, rates, profile: OperatingProfile | None, sn_curve: BasquinCurve | None) -> dict:
    """Per pitch and quantity: the rule-form fit (`rule_form_entry`) and, with `sn_curve`, Miner's sum."""
    shape_rule = WEIBULL_SHAPE[result.options["weibull"]]
    rule = result.rule
    count = result_load_count(result)
    rule_n = None if count is None else count.n_ice_low
    per_hour = rates["loads_per_hour_per_propeller"] if rates else None
    out: dict[str, Any] = {
        "form": "P(X >= x) = exp(-(x/x_max)^k ln N) (notes §7.3, as recalled, verify against the rule text)",
        "rule_n_ice": rule_n,  # per blade, the lower k_1 of a wing propeller
        "rule_n_ice_high": None if count is None else count.n_ice_high,
        "rule_n_ice_inputs": None if count is None else count.as_dict(),
        "operating_profile": None
        if profile is None
        else {
            "hours_in_ice_per_year": profile.hours_in_ice_per_year,
            "years": profile.years,
            "hours": profile.hours,
        },
    }
    for pitch in result.pitches:
        amp = result.amplitudes(pitch)
        label = pitch_label(pitch)
        out[label] = {
            "force_kn": rule_form_entry(
                amp.force_n, 1e3, per_hour, profile, rule and rule.backward_force_n, rule_n, shape_rule
            ),
            "torque_knm": rule_form_entry(
                amp.torque_nm, 1e3, per_hour, profile, rule and rule.max_torque_nm, rule_n, shape_rule
            ),
        }
        if sn_curve is not None and rates:
            values = amp.force_n if sn_curve.quantity == "force" else amp.torque_nm
            damage = miner_damage(values, sn_curve, amp.weight)
            out[label]["miner"] = {
                "quantity": sn_curve.quantity,
                "damage_per_hour": damage / rates["hours_in_ice"],
                "damage_lifetime": None
                if profile is None
                else damage / rates["hours_in_ice"] * profile.hours,
            }
    return out


def build_summary(
    result, table_info, profile: OperatingProfile | None, sn_curve: BasquinCurve | None
) -> dict:
    """The summary dict of a `PropellerResult` (JSON-ready after the writer's sanitising)."""
    loads, run_id = result.loads, result.loads["run_id"]
    runs = sorted(set(run_id.tolist()))
    energy = loads["kinetic_energy_j"]
    rates = _rates(result)
    measured = None
    if result.measured is not None:
        m = result.measured
        measured = {
            "source": m.series.source,
            "n_samples": int(m.series.time_s.size),
            "duration_s": m.series.duration_s,
            "torque_range_knm": finite_range(m.series.torque_nm / 1e3),
            "intervals_above_threshold_knm": m.intervals_knm,
            "envelope_above_threshold_knm": envelope(m.intervals_knm),
        }
    return {
        "options": dict(result.options),
        "propeller": {
            **{k: v for k, v in result.propeller.__dict__.items() if k != "open_water_table"},
            "open_water_curves": "B-series (Oosterveld & van Oossanen 1975)"
            if result.propeller.open_water_table is None
            else f"table {result.propeller.open_water_table.source}",
            "pitch_m": result.propeller.pitch_m,
            "pitch_angle_07R_deg": propeller_pitch_angle_deg(result.propeller, "r07"),
            "pitch_angle_thesis_deg": propeller_pitch_angle_deg(result.propeller, "thesis_r_prop"),
        },
        "n_cusps": int(run_id.size),
        "n_cusps_per_run": {r: int(np.sum(run_id == r)) for r in runs},
        "n_runs": len(runs),
        "n_above_last_class_edge": int(
            np.sum(loads["box_volume_m3"] > result.options["volume_class_edges_m3"][-1])
        ),
        "kinetic_energy_kj": {
            "total": float(energy.sum() / 1e3),
            "max": float(energy.max() / 1e3) if energy.size else None,
            "note": "energy (Eqs. 27-28), not comparable with torque (erratum 25)",
        },
        "pitches": table_info,
        "simulated_torque_above_threshold": torque_ranges_above(result.spectra),
        "measured_torque": measured,
        "ice_class": None if result.rule is None else result.rule.as_dict(),
        "rates": rates,
        "rule_form": _rule_form(result, rates, profile, sn_curve) if run_id.size else None,
        "warnings": beyond_table_warnings(table_info, result.options["beyond"]),
    }
