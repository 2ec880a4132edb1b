"""The ice-class rule's torque excitation as a baseline beside the simulated cusps (docs/shaft.md, "The rule's
excitation"; physics-notes §7.2–7.4, formulas **as recalled**, verify against the rule text).

The rule's milling sequence is one ice block milled over N_Q = 2 H_ice revolutions (H_ice of the polar class
[m]): Z·N_Q blade impacts (`propeller.ruleform.rule_impacts_per_cusp`), each the case's pulse
C_q · Q_max · sin(φ · 180°/α_i) over α_i of propeller rotation (`excitation.EXCITATION_CASES`; case 3 two
blocks, the second shifted by 360°/(2Z)), with Q_max the rule's maximum ice torque
(`propeller.iceclass.ur_i3_loads`, §7.2). The pulses act on the mean torque of the propeller's open-water
operating point (`propeller.operating`), not on a measured mean (§7.4). The same shaft model as the simulated
cusps computes the response: the drive model (torque-limited PI motor, the propeller slows) or the linear
one (constant rpm).

Resonance sweep: the set speed runs through every crossing of a blade-passage order (k Z, k = 1, 2, 3) with a
free-free mode inside the swept range (`resonance.campbell`), at the crossing and ±5 % and ±10 % of it,
plus the nominal speed. Away from the nominal speed the mean torque follows the propeller law,
Q_mean(n) = Q_mean(n_0) (n/n_0)² (the ship's speed taken to scale with the propeller's, so the advance ratio
stays; an assumption of the sweep); Q_max stays at the nominal speed's, as the rule defines it with the
nominal n.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.propeller.iceclass import ur_i3_loads
from floebreak.propeller.ruleform import rule_impacts_per_cusp
from floebreak.propeller.spec import MAX_PROPELLER_RPM, PropellerSpec
from floebreak.shaft.analysis import ShaftResult, shaft_drive_response, shaft_response
from floebreak.shaft.line import ShaftLine
from floebreak.shaft.resonance import DEFAULT_HARMONICS, campbell

RULE_LEAD_S = 2.0  # the block arrives after 2 s of steady running, as the simulated cusps' first
# swept range, fractions of the nominal speed: slow ahead (30 %, assumed) to the Campbell diagram's 110 %
SWEEP_RPM_FRACTION = (0.3, 1.1)
SWEEP_OFFSETS = (-0.10, -0.05, 0.0, 0.05, 0.10)  # around each crossing
EXCITATIONS = ("simulation", "rule")


@dataclass(frozen=True)
class RuleExcitation:
    """One rule milling sequence: the class, H_ice [m], Q_max [N·m] and the blades."""

    polar_class: str
    ice_thickness_m: float
    q_max_n_m: float
    blades: int
    torque_branch: str = ""

    @property
    def revolutions(self) -> float:
        """N_Q = 2 H_ice (H_ice in m)."""
        return 2.0 * self.ice_thickness_m

    @property
    def n_impacts(self) -> int:
        return int(rule_impacts_per_cusp(self.ice_thickness_m, self.blades))

    def as_dict(self) -> dict:
        return {
            "polar_class": self.polar_class,
            "ice_thickness_m": self.ice_thickness_m,
            "q_max_knm": self.q_max_n_m / 1e3,
            "q_max_branch": self.torque_branch,
            "revolutions_n_q": self.revolutions,
            "impacts": self.n_impacts,
            "source": "IACS UR I3 as recalled (physics-notes §7.2–7.3); verify against the rule text",
        }


def rule_excitation(spec: PropellerSpec, polar_class: str) -> RuleExcitation:
    """The rule's milling sequence of the propeller `spec` in `polar_class`."""
    rule = ur_i3_loads(spec, polar_class)
    return RuleExcitation(
        rule.polar_class, rule.ice_thickness_m, rule.max_torque_nm, int(spec.blades), rule.torque_branch
    )


def rule_response(
    excitation: RuleExcitation,
    line: ShaftLine,
    *,
    model: str,
    mean_torque_n_m: float,
    speed_m_s: float,
    rpm: float | None = None,
    cases=(1, 2, 3, 4),
    station: str | None = None,
    torque_limit_n_m: float | None = None,
    progress: Callable[[str, int, int], None] | None = None,
) -> ShaftResult:
    """The shaft's response to the rule's milling sequence (module docstring) with the shaft `model`
    ("drive" or "linear"), at `rpm` (default the line's) on `mean_torque_n_m`."""
    if model not in ("drive", "linear"):
        raise InputError("shaft_model", f"unknown model {model!r}", allowed="drive, linear")
    if model == "drive":
        return shaft_drive_response(
            [RULE_LEAD_S],
            [excitation.n_impacts],
            lambda cusp, rpm_now: excitation.q_max_n_m,
            line,
            speed_m_s=speed_m_s,
            rpm=rpm,
            mean_torque_n_m=mean_torque_n_m,
            torque_limit_n_m=torque_limit_n_m,
            blades=excitation.blades,
            cases=cases,
            station=station,
            progress=progress,
        )
    return shaft_response(
        [0.0],
        [excitation.q_max_n_m],
        [excitation.ice_thickness_m],
        line,
        speed_m_s=speed_m_s,
        rpm=rpm,
        mean_torque_n_m=mean_torque_n_m,
        blades=excitation.blades,
        cases=cases,
        station=station,
        lead_s=RULE_LEAD_S,
        progress=progress,
    )


def case_peaks(result: ShaftResult) -> dict[int, dict]:
    """Per case: Q_peak, the smallest shaft torque, the load peak [kN·m], the dynamic amplification and, for
    the drive model, whether the propeller stopped and its lowest rpm."""
    out = {}
    drive = dict(zip(result.cases, result.drive_summaries, strict=False))
    for case, p in result.peaks().items():
        out[case] = {
            "q_peak_knm": p["q_peak_n_m"] / 1e3,
            "q_min_knm": p["q_min_n_m"] / 1e3,
            "load_peak_knm": p["load_peak_n_m"] / 1e3,
            "dynamic_amplification": p["dynamic_amplification"],
        }
        if case in drive:
            out[case] |= {"stalled": drive[case]["stalled"], "min_rpm": drive[case]["min_rpm"]}
    return out


def sweep_rpms(line: ShaftLine, blades: int, rpm_range: tuple[float, float] | None = None) -> np.ndarray:
    """The set speeds of the resonance sweep (module docstring) [1/min], sorted; `rpm_range` default
    `SWEEP_RPM_FRACTION` of the line's rpm."""
    nominal = line.rpm
    low, high = (f * nominal for f in SWEEP_RPM_FRACTION) if rpm_range is None else rpm_range
    require_range("sweep_rpm.low", low, low=0.0, high=MAX_PROPELLER_RPM, unit="1/min")
    require_range("sweep_rpm.high", high, low=low, high=MAX_PROPELLER_RPM, unit="1/min")
    data = campbell(line, blades=blades, harmonics=DEFAULT_HARMONICS)
    crossings = data.crossing_rpm[(data.crossing_rpm >= low) & (data.crossing_rpm <= high)]
    points = [nominal] + [c * (1.0 + d) for c in crossings for d in SWEEP_OFFSETS]
    points = [p for p in points if low <= p <= high]
    return np.unique(np.round(np.asarray(points, dtype=float), 3))


def rule_resonance_sweep(
    excitation: RuleExcitation,
    line: ShaftLine,
    *,
    model: str,
    mean_torque_n_m: float,
    speed_m_s: float,
    cases=(1, 2, 3, 4),
    station: str | None = None,
    rpm_range: tuple[float, float] | None = None,
    torque_limit_n_m: float | None = None,
) -> dict:
    """Q_peak per case of the rule's excitation at each set speed of `sweep_rpms` (module docstring),
    the mean torque by the propeller law from `mean_torque_n_m` at the line's rpm; JSON-ready (kN·m)."""
    rpms = sweep_rpms(line, excitation.blades, rpm_range)
    data = campbell(line, blades=excitation.blades)
    rows = []
    for rpm in rpms:
        mean = mean_torque_n_m * (rpm / line.rpm) ** 2
        result = rule_response(
            excitation,
            line,
            model=model,
            mean_torque_n_m=mean,
            speed_m_s=speed_m_s,
            rpm=float(rpm),
            cases=cases,
            station=station,
            torque_limit_n_m=torque_limit_n_m,
        )
        peaks = case_peaks(result)
        rows.append({"rpm": float(rpm), "mean_torque_knm": mean / 1e3, "cases": peaks})
    crossings = [
        {"order": int(data.orders[i]), "mode": j + 1, "rpm": float(data.crossing_rpm[i, j])}
        for i in range(data.orders.size)
        for j in range(data.natural_frequency_hz.size)
        if rpms.size and rpms[0] <= data.crossing_rpm[i, j] <= rpms[-1]
    ]
    return {
        "rpm_range": [float(rpms[0]), float(rpms[-1])] if rpms.size else None,
        "crossings": crossings,
        "mean_torque": "propeller law Q_mean(n) = Q_mean(n_0) (n/n_0)^2; Q_max at the nominal speed",
        "points": rows,
    }
