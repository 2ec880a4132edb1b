"""One propeller's and pitch's simulated loads and its design value (pure; the design-load table,
`floebreak.propeller.design_loads`, and the loads' spread, `floebreak.propeller.spread`, use them).

Design value: the rule-form extrapolation x_max over the operating profile's number of loads
(`floebreak.propeller.ruleform.RuleFormFit.x_max`, notes §7.3) where the caller has it, else the largest
simulated load (not extrapolated).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError
from floebreak.propeller.ruleform import fit_rule_form


@dataclass(frozen=True)
class SimulatedLoads:
    """One pitch's simulated loads on one propeller (SI): the largest |Q| and |F| over the runs, and, where
    available, the rule-form x_max over the operating profile, the number of loads over the profile, the
    number of simulated loads, the range of the fitted amplitudes, the blade impacts per hour on one blade
    and the operating profile's hours."""

    max_abs_torque_n_m: float
    max_abs_force_n: float
    n_simulated: int | None = None
    n_loads_profile: float | None = None
    x_max_torque_n_m: float | None = None
    x_max_force_n: float | None = None
    fit_range_torque_n_m: tuple[float, float] | None = None
    fit_range_force_n: tuple[float, float] | None = None
    no_fit_reason: str | None = None
    blade_impacts_per_hour: float | None = None
    profile_hours: float | None = None

    def __post_init__(self) -> None:
        quantities = ("max_abs_torque_n_m", "max_abs_force_n", "n_loads_profile", "blade_impacts_per_hour")
        for name in (*quantities, "x_max_torque_n_m", "x_max_force_n"):
            _check_non_negative(name, getattr(self, name))


def _check_non_negative(name: str, value) -> None:
    if value is not None and not (math.isfinite(value) and value >= 0.0):
        raise InputError(name, f"{value!r}", value=value, allowed="finite, ≥ 0")


def design_value(sim: SimulatedLoads, quantity: str) -> tuple[float, str]:
    """The design torque ("torque") or force ("force") and its basis: x_max over the profile where given,
    else the largest simulated load."""
    if quantity == "torque":
        x_max, largest, fit_range, unit = (
            sim.x_max_torque_n_m,
            sim.max_abs_torque_n_m,
            sim.fit_range_torque_n_m,
            "kN·m",
        )
    else:
        x_max, largest, fit_range, unit = sim.x_max_force_n, sim.max_abs_force_n, sim.fit_range_force_n, "kN"
    n_sim = "" if sim.n_simulated is None else f" of {sim.n_simulated} simulated loads"
    if x_max is None:
        why = "" if sim.no_fit_reason is None else f": {sim.no_fit_reason}"
        return largest, f"largest simulated load{n_sim} (not extrapolated to the operating profile{why})"
    fit = "" if fit_range is None else f", fitted {fit_range[0] / 1e3:.3g}–{fit_range[1] / 1e3:.3g} {unit}"
    over = "" if sim.n_loads_profile is None else f" of N = {sim.n_loads_profile:.3g} loads"
    return (
        x_max,
        f"rule-form x_max over the operating profile{over} (fit on the loads{n_sim}{fit}; notes §7.3)",
    )


def simulated_loads(
    force_n,
    torque_n_m,
    weights=None,
    loads_per_hour: float | None = None,
    profile_hours: float | None = None,
    blade_impacts_per_hour: float | None = None,
) -> SimulatedLoads:
    """One propeller's and pitch's `SimulatedLoads` from its per-cusp |F| [N] and |Q| [N·m] (NaN: no
    load; `weights`: loads per cusp on that propeller, 0 for cusps that do not reach it). With
    `loads_per_hour` and `profile_hours` the number of loads over the profile N = rate × hours and, where
    the rule form fits (`fit_rule_form`, weighted), x_max(N) of each quantity (notes §7.3).
    `blade_impacts_per_hour`: simulated impacts on one blade per hour in ice (for the N_ice comparison)."""
    f, q = np.abs(np.asarray(force_n, dtype=float)), np.abs(np.asarray(torque_n_m, dtype=float))
    w = np.ones(f.shape) if weights is None else np.asarray(weights, dtype=float)
    loaded = (w > 0.0) & np.isfinite(f) & np.isfinite(q)
    n_profile = None
    if loads_per_hour is not None and profile_hours is not None:
        n_profile = loads_per_hour * profile_hours
    out: dict = {
        "max_abs_force_n": float(f[loaded].max()) if loaded.any() else 0.0,
        "max_abs_torque_n_m": float(q[loaded].max()) if loaded.any() else 0.0,
        "n_simulated": int(loaded.sum()),
        "n_loads_profile": n_profile,
        "blade_impacts_per_hour": blade_impacts_per_hour,
        "profile_hours": profile_hours,
    }
    if n_profile is None or n_profile <= 1.0:
        out["no_fit_reason"] = "no operating profile or time base"
    for name, values in (("force_n", f), ("torque_n_m", q)):
        fitted = values[loaded & (values > 0.0)]
        if n_profile is None or n_profile <= 1.0:
            continue
        if fitted.size and np.ptp(fitted) == 0.0:
            out["no_fit_reason"] = f"all {fitted.size} loads are equal, the rule form cannot be fitted"
            continue
        try:
            fit = fit_rule_form(values[loaded], weights=w[loaded])
        except InputError as error:  # too few loads: the design value is the largest simulated load
            out["no_fit_reason"] = f"no rule-form fit ({error})"
            continue
        out[f"x_max_{name}"] = fit.x_max(n_profile)
        out[f"fit_range_{name}"] = (float(fitted.min()), float(fitted.max()))
    return SimulatedLoads(**out)
