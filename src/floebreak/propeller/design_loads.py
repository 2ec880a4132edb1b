"""The design-load table of a propeller: per pitch, the design ice torque and blade force
from the simulation, the ice-class rule's values, their ratio, the basis of every number and the number of
loads over the operating profile against the rule's N_ice (pure; the summary, terminal and report show it).

Design value: the rule-form extrapolation x_max over the operating profile's number of loads
(`floebreak.propeller.ruleform.RuleFormFit.x_max`, notes §7.3) where the caller has it, else the largest
simulated load (not extrapolated). Rule values: IACS UR I3 Q_max and the backward blade force F_b
(`floebreak.propeller.iceclass.ur_i3_loads`, notes §7.2, as recalled); the simulated |F| has no direction,
and is compared with F_b as in the summary's rule form (the forward force F_f is listed beside it). Rule
N_ice: `floebreak.propeller.ruleform.rule_n_ice`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from floebreak.propeller.design_values import SimulatedLoads, design_value, simulated_loads
from floebreak.propeller.iceclass import IceClassLoads, ur_i3_loads
from floebreak.propeller.ruleform import rule_n_ice
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
    rule_n_ice: float
    basis: dict[str, str]

    @property
    def torque_ratio(self) -> float:
        """Design Q / rule Q_max."""
        return self.design_torque_n_m / self.rule_torque_n_m

    @property
    def force_ratio(self) -> float:
        """Design F / rule F_b."""
        return self.design_force_n / self.rule_backward_force_n

    @property
    def loads_ratio(self) -> float | None:
        """Loads over the profile / N_ice (None without a profile)."""
        return None if self.n_loads_profile is None else self.n_loads_profile / self.rule_n_ice

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
            "rule_n_ice": self.rule_n_ice,
            "loads_ratio": self.loads_ratio,
            "basis": dict(self.basis),
        }


@dataclass(frozen=True)
class DesignLoadTable:
    """The design loads of one propeller, one row per pitch, and the rule's loads they are set against."""

    propeller: str
    rule: IceClassLoads
    rule_n_ice: float
    rows: tuple[DesignLoadRow, ...]

    def as_dict(self) -> dict:
        return {
            "propeller": self.propeller,
            "polar_class": self.rule.polar_class,
            "rule_n_ice": self.rule_n_ice,
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
                "loads over profile [-]": row.n_loads_profile,
                "rule N_ice [-]": row.rule_n_ice,
                "loads / N_ice [-]": row.loads_ratio,
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


def design_loads(
    spec: PropellerSpec,
    polar_class: str,
    simulated: Mapping[float, SimulatedLoads],
    *,
    propeller: str = "propeller",
    rule_factor: float = 1.0,
) -> DesignLoadTable:
    """The design-load table of one propeller: `simulated` maps pitch [%] → `SimulatedLoads`; the rule's
    loads and N_ice follow from `spec`, `polar_class` and `rule_factor` (k_1 k_2 k_3 k_4; see the module)."""
    rule = ur_i3_loads(spec, polar_class)
    n_ice = rule_n_ice(polar_class, spec.revolutions_per_s, rule_factor)
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
            "rule N_ice": f"N_ice = k1 k2 k3 k4 N_class n = {rule_factor:g} × N_class({rule.polar_class}) × "
            f"{spec.revolutions_per_s:.4g} 1/s (notes §7, as recalled)",
            "loads over profile": "not given (no time base or operating profile)"
            if sim.n_loads_profile is None
            else "loads per hour on this propeller × operating-profile hours",
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
                n_ice,
                basis,
            )
        )
    return DesignLoadTable(propeller, rule, n_ice, tuple(rows))


def design_load_tables(result: PropellerResult) -> list[DesignLoadTable]:
    """The design-load tables of a `PropellerResult` with a polar class (none without): one per
    propeller where the transport model assigns cusps to propellers ("propeller 1", "propeller 2", … in
    the arrangement's order; default 1 = port, 2 = starboard), else one for the mean propeller (loads per
    cusp f / n_p). Loads per hour from the result's time base, hours from its operating profile."""
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
    tables = []
    for name, members in groups.items():
        simulated = {}
        for pitch in result.pitches:
            amp = result.amplitudes(pitch)
            if members is None:
                weights = amp.weight if np.isfinite(amp.weight).all() else None
                total = None if weights is None else float(np.sum(weights))
            else:
                weights, total = members.astype(float), float(members.sum())
            per_hour = None if total is None or not hours_in_ice else total / hours_in_ice
            simulated[pitch] = simulated_loads(
                amp.force_n, amp.torque_nm, weights, per_hour, profile.get("hours")
            )
        tables.append(
            design_loads(
                result.propeller,
                result.rule.polar_class,
                simulated,
                propeller=name,
                rule_factor=result.options["rule_factor"],
            )
        )
    return tables
