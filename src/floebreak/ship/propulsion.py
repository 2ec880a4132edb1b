"""Ship propulsion in ice: net thrust as a function of speed, and the ship's effective mass in surge.

The net thrust is what the propellers give beyond the open-water resistance, T_net(V) = T(V) − R_ow(V); the
ice force must exceed it for the ship to slow down (docs/model.md, "Ship surge"). Three forms:

- ``"bollard_pull"``: the form behind the Finnish-Swedish ice class rules (Juva & Riska 2002, "On the power
  requirement in the Finnish-Swedish ice class rules", Winter Navigation Research Board Report 53; also
  Riska et al. 1997): T_net(V) = T_B·(1 − V/(3·V_ow) − 2/3·(V/V_ow)²), T_B the bollard pull and V_ow the
  open-water speed (T_net(V_ow) = 0: thrust and open-water resistance balance there).
- ``"power"``: the thrust a delivered power gives, T(V) = min(T_B, η_D·P_D/V) (effective power
  R·V = η_D·P_D, η_D the quasi-propulsive efficiency; e.g. Molland, Turnock & Hudson 2017, *Ship Resistance
  and Propulsion*, 2nd ed.), less an open-water resistance quadratic in speed, R_ow(V) = R_ow(V_ow)·
  (V/V_ow)², through the balance point R_ow(V_ow) = T(V_ow) (a constant resistance coefficient, as in the
  FSICR background's R_ow ∝ V²).
- ``"table"``: net thrust at given speeds (a measured or designed curve), linear between them; the speeds
  rise from 0 and the net thrust falls from the bollard pull (> 0) to ≤ 0 (the open-water speed lies inside).

`bollard_pull_estimate_n`: the estimate of the Finnish-Swedish ice class rules (FSICR, engine output
requirement), T_B = K_e·(P·D_P)^(2/3) with T_B in kN, P in kW and D_P in m;
K_e 0.78 / 0.98 / 1.21 for one / two / three CP or electrically driven propellers (docs/model.md records
which of these values a second source confirms).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from floebreak.errors import InputError, require_range

PropulsionModel = Literal["bollard_pull", "power", "table"]

SURGE_ADDED_MASS = 0.05  # −X_u̇/m of a ship in surge: ≈ 0.05 (Söding 1982, as given by Fossen 2011)
# FSICR, K_e for 1, 2, 3 CP or electrically driven propellers (FP propellers: 0.72, 0.90, 1.12)
FSICR_KE = {1: 0.78, 2: 0.98, 3: 1.21}

KEY = "ship.propulsion"


def juva_riska_net_thrust_n(speed_m_s, bollard_pull_n: float, open_water_speed_m_s: float):
    """T_net(V) = T_B·(1 − u/3 − 2u²/3), u = V/V_ow [N] (Juva & Riska 2002; FSICR guidelines)."""
    u = np.asarray(speed_m_s, dtype=float) / open_water_speed_m_s
    return bollard_pull_n * (1.0 - u / 3.0 - 2.0 * u * u / 3.0)


def power_thrust_n(speed_m_s, delivered_power_w: float, efficiency: float, bollard_pull_n: float):
    """T(V) = min(T_B, η_D·P_D/V) [N]: the effective power T·V = η_D·P_D, limited by the bollard pull."""
    speed = np.maximum(np.asarray(speed_m_s, dtype=float), 1e-12)  # at rest: the bollard pull
    return np.minimum(bollard_pull_n, efficiency * delivered_power_w / speed)


def bollard_pull_estimate_n(power_w: float, propeller_diameter_m: float, n_propellers: int = 2) -> float:
    """T_B = K_e·(P·D_P)^(2/3) (FSICR engine-output requirement; kN with P in kW and D_P in m), in N."""
    require_range("power_w", power_w, low=0.0, unit="W")
    require_range("propeller_diameter_m", propeller_diameter_m, low=0.0, unit="m")
    if n_propellers not in FSICR_KE:
        raise InputError("n_propellers", repr(n_propellers), allowed="1, 2 or 3 (FSICR K_e)")
    return 1e3 * FSICR_KE[n_propellers] * (power_w / 1e3 * propeller_diameter_m) ** (2.0 / 3.0)


@dataclass(frozen=True)
class Propulsion:
    """A ship's propulsion in ice and its surge mass (the scenario table ``[ship.propulsion]``).

    `displacement_kg` Δ and `added_mass_coefficient` C_a give the effective mass m = Δ·(1 + C_a). Only
    the fields of the chosen `model` are used (module docstring); each is checked on construction.
    """

    model: PropulsionModel
    displacement_kg: float
    added_mass_coefficient: float = SURGE_ADDED_MASS
    bollard_pull_n: float | None = None
    open_water_speed_m_s: float | None = None
    delivered_power_w: float | None = None
    propulsive_efficiency: float | None = None
    speeds_m_s: tuple[float, ...] = ()
    net_thrust_n: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        require_range(f"{KEY}.displacement_kg", self.displacement_kg, low=0.0, unit="kg")
        require_range(
            f"{KEY}.added_mass_coefficient",
            self.added_mass_coefficient,
            low=0.0,
            high=1.0,
            low_inclusive=True,
        )
        needed = {
            "bollard_pull": ("bollard_pull_n", "open_water_speed_m_s"),
            "power": ("bollard_pull_n", "open_water_speed_m_s", "delivered_power_w", "propulsive_efficiency"),
            "table": ("speeds_m_s", "net_thrust_n"),
        }
        if self.model not in needed:
            raise InputError(f"{KEY}.model", repr(self.model), allowed=", ".join(needed))
        for name in needed[self.model]:
            if getattr(self, name) in (None, ()):
                raise InputError(f"{KEY}.{name}", f"required with model = {self.model!r}")
        for name in ("bollard_pull_n", "open_water_speed_m_s", "delivered_power_w"):
            if name in needed[self.model]:
                require_range(f"{KEY}.{name}", getattr(self, name), low=0.0)
        if self.model == "power":
            require_range(f"{KEY}.propulsive_efficiency", self.propulsive_efficiency, low=0.0, high=1.0)
        if self.model == "table":
            check_table(self.speeds_m_s, self.net_thrust_n)

    @property
    def effective_mass_kg(self) -> float:
        """m = Δ·(1 + C_a): displacement plus the surge added mass."""
        return self.displacement_kg * (1.0 + self.added_mass_coefficient)

    @property
    def bollard_thrust_n(self) -> float:
        """T_net(0): the net thrust at rest; an ice force above it stops the ship."""
        return float(net_thrust_n(self, 0.0))


def check_table(speeds_m_s, net_thrust_n) -> None:
    """A net-thrust table: equally long, ≥ 2 rows, speeds rising strictly from 0, net thrust falling strictly
    from a bollard pull > 0 to ≤ 0 at the last speed (so the open-water speed lies in the table)."""
    speeds, thrust = np.asarray(speeds_m_s, dtype=float), np.asarray(net_thrust_n, dtype=float)
    if speeds.ndim != 1 or speeds.size < 2 or speeds.shape != thrust.shape:
        raise InputError(
            f"{KEY}.net_thrust_n",
            f"{thrust.size} values for {speeds.size} speeds",
            allowed="as many net thrusts as speeds, at least 2",
        )
    if not (np.isfinite(speeds).all() and np.isfinite(thrust).all()):
        raise InputError(f"{KEY}.speeds_m_s", "values must be finite")
    if speeds[0] != 0.0 or not (np.diff(speeds) > 0.0).all():
        raise InputError(
            f"{KEY}.speeds_m_s",
            f"{speeds.tolist()} does not rise strictly from 0",
            allowed="0 = V_0 < V_1 < … m/s",
        )
    if not (np.diff(thrust) < 0.0).all():
        raise InputError(
            f"{KEY}.net_thrust_n",
            f"{thrust.tolist()} does not fall strictly with speed",
            allowed="T_0 > T_1 > … N (net thrust decreases with speed)",
        )
    if not thrust[0] > 0.0:
        raise InputError(
            f"{KEY}.net_thrust_n", f"the bollard pull {thrust[0]:g} N is not > 0", allowed="> 0 N"
        )
    if thrust[-1] > 0.0:
        raise InputError(
            f"{KEY}.net_thrust_n",
            f"{thrust[-1]:g} N at the last speed is > 0",
            allowed="≤ 0 N at the last speed (the open-water speed inside the table)",
        )


def net_thrust_n(propulsion: Propulsion, speed_m_s):
    """T_net(V) = T(V) − R_ow(V) [N] of `propulsion` at `speed_m_s` (≥ 0; scalar or array)."""
    p = propulsion
    if p.model == "bollard_pull":
        return juva_riska_net_thrust_n(speed_m_s, p.bollard_pull_n, p.open_water_speed_m_s)
    if p.model == "power":
        thrust = power_thrust_n(speed_m_s, p.delivered_power_w, p.propulsive_efficiency, p.bollard_pull_n)
        at_balance = power_thrust_n(
            p.open_water_speed_m_s, p.delivered_power_w, p.propulsive_efficiency, p.bollard_pull_n
        )
        return thrust - open_water_resistance_n(speed_m_s, float(at_balance), p.open_water_speed_m_s)
    speeds = np.asarray(p.speeds_m_s, dtype=float)
    thrust = np.asarray(p.net_thrust_n, dtype=float)
    speed = np.asarray(speed_m_s, dtype=float)
    slope = (thrust[-1] - thrust[-2]) / (speeds[-1] - speeds[-2])  # beyond the table: its last slope
    beyond = thrust[-1] + slope * (speed - speeds[-1])
    return np.where(speed > speeds[-1], beyond, np.interp(speed, speeds, thrust))


def open_water_resistance_n(speed_m_s, resistance_at_ow_n: float, open_water_speed_m_s: float):
    """R_ow(V) = R_ow(V_ow)·(V/V_ow)² [N]: constant resistance coefficient through the balance point."""
    u = np.asarray(speed_m_s, dtype=float) / open_water_speed_m_s
    return resistance_at_ow_n * u * u


def balance_speed_m_s(propulsion: Propulsion, ice_force_n: float = 0.0) -> float:
    """The speed at which T_net(V) = `ice_force_n` (the steady speed under a constant ice force); 0 if the
    force is at least the bollard pull. T_net falls with speed in every form, so the root is unique."""
    from scipy.optimize import brentq

    def excess(v: float) -> float:
        return float(net_thrust_n(propulsion, v)) - ice_force_n

    if excess(0.0) <= 0.0:
        return 0.0
    high = 1.0
    while excess(high) > 0.0:
        high *= 2.0
        if high > 1e3:
            return math.inf
    return float(brentq(excess, 0.0, high, xtol=1e-12, rtol=1e-12))
