"""IACS UR I3 open-propeller ice loads: a plausibility cap beyond the thesis (physics-notes §7.2–7.3).

The formulas are those of UR I3 (2006 / Rev.1 2007) *as recalled* in the notes (§7.2, confidence medium);
UR I3 was revised in Rev.2 (2023). Assumptions: magnitudes only (backward loads are sometimes given with a
minus sign); n = nominal rotational speed [1/s]; P_0.7 = bollard pitch, else 0.7 × maximum pitch (the rule's
fallback); EAR, Z, d/D and t_0.7 of the Agulhas II are assumptions (notes §7.1). Input D in m, output SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from floebreak.errors import InputError
from floebreak.propeller.spec import PropellerSpec

# class: (H_ice [m], S_ice, S_qice)  (notes §7.2 table)
POLAR_CLASSES = {
    "PC1": (4.0, 1.2, 1.15),
    "PC2": (3.5, 1.1, 1.15),
    "PC3": (3.0, 1.1, 1.15),
    "PC4": (2.5, 1.1, 1.15),
    "PC5": (2.0, 1.1, 1.15),
    "PC6": (1.75, 1.0, 1.0),
    "PC7": (1.5, 1.0, 1.0),
}
WEIBULL_SHAPE = {"open": 0.75, "ducted": 1.0}


@dataclass(frozen=True)
class IceClassLoads:
    """Rule maxima for one polar class and propeller, with the formula branch taken for each."""

    polar_class: str
    ice_thickness_m: float
    backward_force_n: float
    forward_force_n: float
    max_torque_nm: float
    backward_branch: str
    forward_branch: str
    torque_branch: str

    def as_dict(self) -> dict:
        return dict(self.__dict__)


def check_polar_class(polar_class: str) -> str:
    key = str(polar_class).strip().upper()
    if key not in POLAR_CLASSES:
        raise InputError(
            "polar_class",
            f"unknown polar class {polar_class!r}",
            value=polar_class,
            allowed=", ".join(POLAR_CLASSES),
        )
    return key


def ur_i3_loads(spec: PropellerSpec, polar_class: str) -> IceClassLoads:
    """Backward blade force F_b, forward blade force F_f [N] and maximum ice torque Q_max [N·m] (notes §7.2).

    F_b = 27 S_ice (nD)^0.7 (EAR/Z)^0.3 D²  [kN]            if D ≤ D_lim = 0.85 H_ice^1.4
        = 23 S_ice (nD)^0.7 (EAR/Z)^0.3 D H_ice^1.4  [kN]    otherwise
    F_f = 250 (EAR/Z) D²  [kN]                               if D ≤ D_lim = 2 H_ice / (1 − d/D)
        = 500 H_ice (EAR/Z) D / (1 − d/D)  [kN]              otherwise
    Q_max = 105 (1 − d/D) S_qice (P_0.7/D)^0.16 (t_0.7/D)^0.6 (nD)^0.17 D³  [kN·m]   if D ≤ D_lim = 1.8 H_ice
          = 202 (1 − d/D) S_qice H_ice^1.1 (P_0.7/D)^0.16 (t_0.7/D)^0.6 (nD)^0.17 D^1.9  [kN·m]  otherwise
    """
    key = check_polar_class(polar_class)
    h_ice, s_ice, s_qice = POLAR_CLASSES[key]
    d = spec.diameter_m
    nd = spec.revolutions_per_s * d
    ear_z = spec.expanded_area_ratio / spec.blades
    hub = spec.hub_ratio
    if d <= 0.85 * h_ice**1.4:
        f_b, b_branch = 27.0 * s_ice * nd**0.7 * ear_z**0.3 * d**2, "D <= 0.85 H_ice^1.4"
    else:
        f_b, b_branch = 23.0 * s_ice * nd**0.7 * ear_z**0.3 * d * h_ice**1.4, "D > 0.85 H_ice^1.4"
    if d <= 2.0 * h_ice / (1.0 - hub):
        f_f, f_branch = 250.0 * ear_z * d**2, "D <= 2 H_ice/(1-d/D)"
    else:
        f_f, f_branch = 500.0 * h_ice * ear_z * d / (1.0 - hub), "D > 2 H_ice/(1-d/D)"
    common = (
        (1.0 - hub)
        * s_qice
        * (spec.rule_pitch_m / d) ** 0.16
        * (spec.blade_thickness_07_m / d) ** 0.6
        * nd**0.17
    )
    if d <= 1.8 * h_ice:
        q, q_branch = 105.0 * common * d**3, "D <= 1.8 H_ice"
    else:
        q, q_branch = 202.0 * common * h_ice**1.1 * d**1.9, "D > 1.8 H_ice"
    return IceClassLoads(key, h_ice, f_b * 1e3, f_f * 1e3, q * 1e3, b_branch, f_branch, q_branch)


def weibull_exceedance(x, n_ice: float, shape: float = WEIBULL_SHAPE["open"]) -> np.ndarray:
    """P(F ≥ x F_max) = exp(−x^k ln N_ice) (notes §7.3; k = 0.75 open, 1.0 ducted)."""
    if not n_ice > 1:
        raise InputError("n_ice", f"{n_ice!r} load cycles", value=n_ice, allowed="> 1")
    x = np.clip(np.asarray(x, dtype=float), 0.0, None)
    return np.exp(-(x**shape) * np.log(n_ice))


def empirical_exceedance(values) -> tuple[np.ndarray, np.ndarray]:
    """Sorted finite values and P(X ≥ value) = (n − i)/n for the i-th smallest (0-based)."""
    v = np.sort(np.asarray(values, dtype=float)[np.isfinite(values)])
    n = v.size
    return v, (n - np.arange(n)) / max(n, 1)
