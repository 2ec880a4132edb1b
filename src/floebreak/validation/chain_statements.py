"""The end-to-end rows of `floebreak validate thesis`: the propeller/shaft chain of the
`default` profile against the thesis' measured shaft torque (§6.2) and against the ice-class rule (PC5).

The rows are data, with the thesis' statements (``floebreak/data/thesis_statements.toml``, loaded by
`floebreak.validation.statements`); they must hold for `default`:

- ``S62.chain.max``: the simulated shaft torque's maximum within 400 kN·m × [0.67, 1.5];
- ``S62.chain.overlap``: its range above 0.1 %/(kN·m) overlaps the measured 58–152 kN·m by ≥ half of it;
- ``S62.chain.end``: that range ends at ≤ 1.5 × 152 = 228 kN·m;
- ``PC5.lifetime_max``: the lifetime maximum of the per-cusp torque at the propeller's pitch over the
  README's operating profile (1000 h/year × 25 years) is at most the rule's Q_max (ratio ≤ 1);
- ``PC5.rate``: blade loads per hour (impacts on one blade) within a factor 3 of the rule's N_ice over the
  operating profile's hours.

Per-run metrics (`chain_6_2_metrics` on the h = 0.4 m runs, `pc5_metrics` on the reference runs) read a run
directory and run the chain; the judges (`shaft_range_measures`, `lifetime_max_ratio`, `blade_load_rate`)
are pure, on plain arrays. A failing row carries its failing link, measured (docs/propeller.md, "Selection
log"; docs/shaft.md §6), as a note.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

# thesis §6.2 / Fig. 35: the measured range with density above 0.1 %/(kN·m); the rows' limits are data
MEASURED_ABOVE_KNM = (58.0, 152.0)
CHAIN_SPEED_M_S, CHAIN_CASE = 3.0, 1  # thesis Eq. 28; the default excitation case
# thesis §6.2: the measured mean shaft torque; compared with the model's own mean, never used as it
MEASURED_MEAN_TORQUE_N_M = 105e3
OPERATING_HOURS_PER_YEAR, OPERATING_YEARS, POLAR_CLASS = 1000.0, 25.0, "PC5"  # the README's profile

PC5_METRICS = ("pc5_lifetime_max_over_q_max", "pc5_blade_loads_over_rule_rate")


def shaft_range_measures(shaft_torque_knm, bin_knm: float = 10.0) -> dict[str, float]:
    """Maximum [kN·m], the envelope of the range with density above 0.1 %/(kN·m) (`bin_knm` bins, as the
    thesis' Fig. 35 and `shaft.analysis.torque_densities`), its overlap with the measured 58–152 kN·m and
    its end; NaN where nothing lies above the threshold."""
    from floebreak.shaft.analysis import torque_densities

    q = np.asarray(shaft_torque_knm, dtype=float).reshape(-1)
    _, dens = torque_densities({"shaft": q}, bin_knm)
    env = dens["shaft"]["envelope_knm"]
    lo, hi = (math.nan, math.nan) if env is None else (float(env[0]), float(env[1]))
    overlap = max(0.0, min(hi, MEASURED_ABOVE_KNM[1]) - max(lo, MEASURED_ABOVE_KNM[0])) if env else math.nan
    return {
        "chain_shaft_max_knm": float(q.max()) if q.size else math.nan,
        "chain_range_start_knm": lo,
        "chain_range_end_knm": hi,
        "chain_range_overlap_knm": overlap,
    }


def lifetime_max_ratio(torque_knm, q_max_knm: float, fitted_lifetime_max_knm: float | None) -> float:
    """Lifetime maximum / Q_max: the rule-form fit's lifetime x_max where it exists, else the largest
    per-cusp |Q| (a lower bound: with one ice thickness every cusp has the same milling torque)."""
    top = float(np.max(np.abs(torque_knm))) if np.size(torque_knm) else math.nan
    best = fitted_lifetime_max_knm if fitted_lifetime_max_knm is not None else top
    return max(best, top) / q_max_knm


def blade_load_rate(loads_per_propeller, n_impacts, blades: int, hours_in_ice: float) -> float:
    """Blade impacts per hour on one blade: Σ (loads on one propeller × impacts per cusp) / Z / hours."""
    weight = np.asarray(loads_per_propeller, dtype=float)
    impacts = np.asarray(n_impacts, dtype=float)
    return float(np.sum(weight * impacts)) / blades / hours_in_ice if hours_in_ice > 0 else math.nan


def chain_6_2_metrics(run_dir: Path) -> dict[str, float]:
    """The §6.2 chain of the default profile on one run's cusps, exactly as `floebreak propeller RUN
    --shaft-line agulhas_ii --speed-m-s 3` computes it (`app.shaft.shaft_analysis_of_run`: transport →
    port propeller, milling torque at the current rpm, drive model, excitation case 1). The mean torque is
    the propeller's own operating point (`propeller.operating`: open-water curves at the rated torque);
    the measured 105 kN·m is only compared with. Returns the `shaft_range_measures` of the station torque,
    the model's mean torque and the pitch ratio the measured mean identifies."""
    from floebreak.app.shaft import shaft_analysis_of_run

    prepared = shaft_analysis_of_run(
        run_dir,
        "agulhas_ii",
        speed_m_s=CHAIN_SPEED_M_S,
        mean_torque_knm=MEASURED_MEAN_TORQUE_N_M / 1e3,
        cases=(CHAIN_CASE,),
    )
    point = prepared.extra_summary["propeller_operating_point"]
    identified = point.get("identified_pitch_ratio")
    return shaft_range_measures(prepared.result.shaft_torque_n_m[0] / 1e3) | {
        "chain_model_mean_torque_knm": float(point["model_mean_torque_knm"]),
        "chain_identified_pitch_ratio": math.nan if identified is None else float(identified),
    }


def pc5_metrics(run_dir: Path) -> dict[str, float]:
    """The propeller analysis of one run at PC5 over the README's operating profile (load model and
    transport of the run's profile): lifetime max / Q_max and blade loads per hour / the rule's rate."""
    from floebreak.app.inputs import shipped_fem_tables
    from floebreak.config.analysis import propeller_defaults
    from floebreak.output.run_files import load_cusps, parquet_metadata, read_resolved_scenario
    from floebreak.propeller.pipeline import analyse_cusp_loads
    from floebreak.propeller.ruleform import OperatingProfile
    from floebreak.propeller.runs import run_inputs, transit_distance_m
    from floebreak.propeller.spectra import pitch_label

    run_dir = Path(run_dir)
    scenario = read_resolved_scenario(run_dir)
    transit = transit_distance_m(
        parquet_metadata(run_dir / "field.parquet"), parquet_metadata(run_dir / "pieces.parquet")
    )
    cusps = load_cusps(run_dir)
    inputs = run_inputs(run_dir, cusps, {run_dir.name: (run_dir, scenario, transit)})
    load_model, transport = propeller_defaults(inputs.profile)
    profile = OperatingProfile(hours_in_ice_per_year=OPERATING_HOURS_PER_YEAR, years=OPERATING_YEARS)
    result = analyse_cusp_loads(
        inputs.cusps,
        load_model=load_model,
        fem_tables=shipped_fem_tables() if load_model == "fem" else None,
        transport=transport,
        polar_class=POLAR_CLASS,
        exposures=inputs.exposures,
        operating_profile=profile,
    )
    s, spec = result.summary, result.propeller
    pitch = max(result.pitches)
    label = pitch_label(pitch)
    fit = (s.get("rule_form") or {}).get(label, {}).get("torque_knm", {})
    weight = np.asarray(result.loads["loads_per_propeller"], dtype=float)
    torque_knm = np.asarray(result.loads[f"torque_nm_{label}"], dtype=float) / 1e3
    loading = (weight > 0.0) & np.isfinite(torque_knm)
    q_max_knm = s["ice_class"]["max_torque_nm"] / 1e3
    ratio = lifetime_max_ratio(torque_knm[loading], q_max_knm, fit.get("x_max_lifetime"))
    impacts = result.loads.get(f"n_impacts_{label}")
    if impacts is None:  # FEM tables: the thesis' 2hZ impacts per cusp
        impacts = np.maximum(np.rint(2.0 * result.loads["thickness_m"] * spec.blades), 1.0)
    rate = blade_load_rate(weight, impacts, spec.blades, s["rates"]["hours_in_ice"])
    rule_rate = s["rule_form"]["rule_n_ice"] / profile.hours
    return dict(zip(PC5_METRICS, (ratio, rate / rule_rate), strict=True))


def chain_metrics(run_dir: Path, *, torque: bool, forces: bool) -> dict[str, float]:
    """The chain rows' metrics of one run of the `default` profile (none for other profiles, whose rows
    do not hold them): the §6.2 chain on the torque point's runs (h = 0.4 m), PC5 on the force points'
    runs (the reference and, unused, the Polarstern)."""
    from floebreak.output.run_files import read_resolved_scenario

    if (read_resolved_scenario(run_dir, strict=False) or {}).get("profile", "default") != "default":
        return {}
    out: dict[str, float] = {}
    if torque:
        out.update(chain_6_2_metrics(run_dir))
    if forces:
        out.update(pc5_metrics(run_dir))
    return out
