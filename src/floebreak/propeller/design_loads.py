"""The design-load table of a propeller: per pitch, the design ice torque and blade force
from the simulation, the ice-class rule's values, their ratio, the basis of every number and the simulated
blade impacts against the rule's N_ice in the same unit, load cycles on one blade, per hour and over the
operating profile (pure; the summary, terminal and report show it).

Design value: the rule-form extrapolation x_max over the operating profile's number of loads
(`floebreak.propeller.ruleform.RuleFormFit.x_max`, notes §7.3) where the caller has it, else the largest
simulated load (not extrapolated). Rule values: IACS UR I3 Q_max and the backward blade force F_b
(`floebreak.propeller.iceclass.ur_i3_loads`, notes §7.2, as recalled); the simulated |F| has no direction,
and is compared with F_b as in the summary's rule form (the forward force F_f is listed beside it). Rule
N_ice per blade: `floebreak.propeller.ruleform.rule_load_count` (k_1 of a wing propeller low and high).
Simulated blade impacts on one blade: Σ over the cusps reaching the propeller of Z·N_Q impacts per cusp
(N_Q = 2 h revolutions, `ruleform.rule_impacts_per_cusp`, as the shaft's excitation), divided by Z.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from floebreak.propeller.design_values import SimulatedLoads, design_value, simulated_loads
from floebreak.propeller.iceclass import IceClassLoads, ur_i3_loads
from floebreak.propeller.ruleform import (
    RuleArrangement,
    RuleLoadCount,
    rule_impacts_per_cusp,
    rule_load_count,
)
from floebreak.propeller.spec import PropellerSpec

if TYPE_CHECKING:
    from floebreak.propeller.pipeline import PropellerResult

RULE_SOURCE = "IACS UR I3 (2006/Rev.1, as recalled: physics-notes §7.2; verify against the rule text)"


@dataclass(frozen=True)
class DesignLoadRow:
    """One pitch's design loads against the rule (SI), with the basis of each number."""

    propeller: str
    pitch_percent: float
    max_abs_torque_n_m: float
    design_torque_n_m: float
    rule_torque_n_m: float
    max_abs_force_n: float
    design_force_n: float
    rule_backward_force_n: float
    rule_forward_force_n: float
    n_loads_profile: float | None
    rule_count: RuleLoadCount
    basis: dict[str, str]
    blade_impacts_per_hour: float | None = None
    profile_hours: float | None = None

    @property
    def torque_ratio(self) -> float:
        """Design Q / rule Q_max."""
        return self.design_torque_n_m / self.rule_torque_n_m

    @property
    def force_ratio(self) -> float:
        """Design F / rule F_b."""
        return self.design_force_n / self.rule_backward_force_n

    @property
    def blade_impacts_profile(self) -> float | None:
        """Simulated impacts on one blade over the operating profile (None without a time base or profile)."""
        if self.blade_impacts_per_hour is None or self.profile_hours is None:
            return None
        return self.blade_impacts_per_hour * self.profile_hours

    def rule_cycles_per_hour(self) -> tuple[float, float] | None:
        """The rule's N_ice per blade spread over the profile's hours (k_1 low, high), None without one."""
        if not self.profile_hours:
            return None
        return (
            self.rule_count.n_ice_low / self.profile_hours,
            self.rule_count.n_ice_high / self.profile_hours,
        )

    def impacts_ratio(self) -> tuple[float, float] | None:
        """Simulated blade impacts over the profile / N_ice per blade (k_1 low, high)."""
        n = self.blade_impacts_profile
        if n is None:
            return None
        return (n / self.rule_count.n_ice_low, n / self.rule_count.n_ice_high)

    def as_dict(self) -> dict:
        """JSON-ready, in kN and kN·m, units in the keys."""
        return {
            "propeller": self.propeller,
            "pitch_percent": self.pitch_percent,
            "max_abs_torque_kn_m": self.max_abs_torque_n_m / 1e3,
            "design_torque_kn_m": self.design_torque_n_m / 1e3,
            "rule_max_torque_kn_m": self.rule_torque_n_m / 1e3,
            "torque_ratio": self.torque_ratio,
            "max_abs_force_kn": self.max_abs_force_n / 1e3,
            "design_force_kn": self.design_force_n / 1e3,
            "rule_backward_force_kn": self.rule_backward_force_n / 1e3,
            "rule_forward_force_kn": self.rule_forward_force_n / 1e3,
            "force_ratio": self.force_ratio,
            "n_loads_profile": self.n_loads_profile,
            **self._count_dict(),
            "basis": dict(self.basis),
        }

    def _count_dict(self) -> dict:
        """Blade impacts against N_ice, both per blade (per hour and over the profile; k_1 low and high)."""
        per_hour, ratio = self.rule_cycles_per_hour(), self.impacts_ratio()
        return {
            "blade_impacts_per_hour": self.blade_impacts_per_hour,
            "rule_blade_cycles_per_hour_low": None if per_hour is None else per_hour[0],
            "rule_blade_cycles_per_hour_high": None if per_hour is None else per_hour[1],
            "blade_impacts_profile": self.blade_impacts_profile,
            "rule_n_ice": self.rule_count.n_ice_low,
            "rule_n_ice_high": self.rule_count.n_ice_high,
            "impacts_ratio_low": None if ratio is None else ratio[0],
            "impacts_ratio_high": None if ratio is None else ratio[1],
        }


@dataclass(frozen=True)
class DesignLoadTable:
    """The design loads of one propeller, one row per pitch, and the rule's loads they are set against."""

    propeller: str
    rule: IceClassLoads
    rule_count: RuleLoadCount
    rows: tuple[DesignLoadRow, ...]

    @property
    def rule_n_ice(self) -> float:
        """N_ice per blade at the lower k_1."""
        return self.rule_count.n_ice_low

    def as_dict(self) -> dict:
        return {
            "propeller": self.propeller,
            "polar_class": self.rule.polar_class,
            "rule_n_ice": self.rule_count.n_ice_low,
            "rule_n_ice_high": self.rule_count.n_ice_high,
            "rule_n_ice_inputs": self.rule_count.as_dict(),
            "rows": [row.as_dict() for row in self.rows],
        }

    def to_rows(self) -> list[dict[str, object]]:
        """Table rows, a unit in every header (kN, kN·m; [-] for counts and ratios)."""
        return [
            {
                "propeller": row.propeller,
                "pitch [%]": row.pitch_percent,
                "max |Q| [kN·m]": row.max_abs_torque_n_m / 1e3,
                "design Q [kN·m]": row.design_torque_n_m / 1e3,
                "rule Q_max [kN·m]": row.rule_torque_n_m / 1e3,
                "Q / Q_max [-]": row.torque_ratio,
                "max |F| [kN]": row.max_abs_force_n / 1e3,
                "design F [kN]": row.design_force_n / 1e3,
                "rule F_b [kN]": row.rule_backward_force_n / 1e3,
                "F / F_b [-]": row.force_ratio,
                "blade impacts per hour [1/h]": row.blade_impacts_per_hour,
                "blade impacts over profile [-]": row.blade_impacts_profile,
                "rule N_ice per blade, k1 low [-]": row.rule_count.n_ice_low,
                "rule N_ice per blade, k1 high [-]": row.rule_count.n_ice_high,
            }
            for row in self.rows
        ]

    def basis_rows(self) -> list[dict[str, object]]:
        """The basis of every number: one row per (pitch, number)."""
        return [
            {"propeller": row.propeller, "pitch [%]": row.pitch_percent, "number": key, "basis": text}
            for row in self.rows
            for key, text in row.basis.items()
        ]


def _count_basis(count: RuleLoadCount, sim: SimulatedLoads) -> dict[str, str]:
    """The basis of the rule's N_ice and of the simulated blade impacts."""
    k1 = "/".join(f"{k:g}" for k in sorted(set(count.k1)))
    return {
        "rule N_ice": f"N_ice per blade = k1 k2 k3 k4 N_class n = {k1} × {count.k2:.3g} × {count.k3:g} × "
        f"{count.k4:g} × {count.n_class:.3g} × {count.revolutions_per_s:.4g} 1/s ({count.location} "
        f"propeller, k1 low/high; k2 at f = {count.submersion_f:.3g}; k4 not recalled: 1; notes §7.4, as "
        "recalled)",
        "blade impacts": "not given (no time base)"
        if sim.blade_impacts_per_hour is None
        else "cusps reaching this propeller × Z·N_Q impacts each (N_Q = 2 h revolutions, notes §7.3) / Z, "
        "per hour in ice",
    }


def design_loads(
    spec: PropellerSpec,
    polar_class: str,
    simulated: Mapping[float, SimulatedLoads],
    *,
    propeller: str = "propeller",
    arrangement: RuleArrangement | None = None,
) -> DesignLoadTable:
    """The design-load table of one propeller: `simulated` maps pitch [%] → `SimulatedLoads`; the rule's
    loads and N_ice per blade follow from `spec`, `polar_class` and `arrangement` (k_1–k_3; the module)."""
    rule = ur_i3_loads(spec, polar_class)
    count = rule_load_count(polar_class, spec, arrangement)
    rows = []
    for pitch in sorted(simulated):
        sim = simulated[pitch]
        q, q_basis = design_value(sim, "torque")
        f, f_basis = design_value(sim, "force")
        basis = {
            "design Q": q_basis,
            "design F": f_basis,
            "rule Q_max": f"{RULE_SOURCE}, {rule.polar_class}, branch {rule.torque_branch}",
            "rule F_b": f"{RULE_SOURCE}, {rule.polar_class}, branch {rule.backward_branch}; "
            f"|F| compared with the backward force (F_f = {rule.forward_force_n / 1e3:.4g} kN)",
            **_count_basis(count, sim),
            "loads over profile": "not given (no time base or operating profile)"
            if sim.n_loads_profile is None
            else "cusps per hour on this propeller × operating-profile hours",
        }
        rows.append(
            DesignLoadRow(
                propeller,
                float(pitch),
                sim.max_abs_torque_n_m,
                q,
                rule.max_torque_nm,
                sim.max_abs_force_n,
                f,
                rule.backward_force_n,
                rule.forward_force_n,
                sim.n_loads_profile,
                count,
                basis,
                sim.blade_impacts_per_hour,
                sim.profile_hours,
            )
        )
    return DesignLoadTable(propeller, rule, count, tuple(rows))


def design_load_tables(result: PropellerResult) -> list[DesignLoadTable]:
    """The design-load tables of a `PropellerResult` with a polar class (none without): one per
    propeller where the transport model assigns cusps to propellers ("propeller 1", "propeller 2", … in
    the arrangement's order; default 1 = port, 2 = starboard), else one for the mean propeller (loads per
    cusp f / n_p). Loads per hour from the result's time base, hours from its operating profile; blade
    impacts per hour: the module docstring's count over the same cusps."""
    if result.rule is None:
        return []
    summary = result.summary
    rates = summary.get("rates") or {}
    hours_in_ice = rates.get("hours_in_ice")
    profile = (summary.get("rule_form") or {}).get("operating_profile") or {}
    index = result.loads.get("propeller_index")
    per_propeller = (summary.get("transport") or {}).get("rule") in ("hull", "flow") and index is not None
    groups: dict[str, np.ndarray | None] = {"one propeller (mean)": None}
    if per_propeller:
        n = max(len(summary["transport"].get("fraction_reaching_per_propeller") or []), int(index.max()) + 1)
        groups = {f"propeller {k + 1}": index == k for k in range(n)}
    blades = result.propeller.blades
    per_blade = rule_impacts_per_cusp(result.loads["thickness_m"], blades) / blades  # N_Q per cusp
    arrangement = RuleArrangement(**result.options.get("rule_arrangement", {}))
    tables = []
    for name, members in groups.items():
        simulated = {}
        for pitch in result.pitches:
            amp = result.amplitudes(pitch)
            if members is None:
                weights = amp.weight if np.isfinite(amp.weight).all() else None
            else:
                weights = members.astype(float)
            total = None if weights is None else float(np.sum(weights))
            per_hour = None if total is None or not hours_in_ice else total / hours_in_ice
            impacts = None if weights is None or not hours_in_ice else float(np.sum(weights * per_blade))
            simulated[pitch] = simulated_loads(
                amp.force_n,
                amp.torque_nm,
                weights,
                per_hour,
                profile.get("hours"),
                None if impacts is None else impacts / hours_in_ice,
            )
        tables.append(
            design_loads(
                result.propeller, result.rule.polar_class, simulated, propeller=name, arrangement=arrangement
            )
        )
    return tables
