"""The propeller's operating point in ice, from its own open-water curves (pure).

- **Wake fraction** (default): Holtrop & Mennen (1982), "An approximate power prediction method",
  International Shipbuilding Progress 29(335), twin-screw formula w = 0.3095 C_B + 10 C_V C_B − 0.23 D/√(B T),
  with the viscous resistance coefficient C_V = (1 + k) C_F + C_A, C_F the ITTC-57 line 0.075/(log₁₀ Re − 2)²
  at Re = V L/ν. Agulhas II: L = 121.8 m (L_pp, physics-notes §6.1), B = 21.7 m, T = 7.65 m (thesis §3),
  D = 4.3 m; C_B = 0.65, 1 + k = 1.2 and C_A = 0.0004 ASSUMED (typical of a full-bodied twin-screw
  polar vessel; docs/explanation/cusp-flow.md). It gives w ≈ 0.14 at 3 m/s.
- **Open-water point**: `open_water.operating_point` at the spec's P/D, area ratio, blades and rpm, on the
  B-series polynomials or, where the spec has one (`PropellerSpec.open_water_table`), on a given table.
- **Constant-rpm pitch control**: a controllable-pitch propeller run at constant speed has its pitch
  reduced by the controller when the open-water torque at the set pitch exceeds the motor's rated torque,
  to the pitch that gives the rated torque (the combinator/load-control principle, Carlton, "Marine
  Propellers and Propulsion", ch. 11 on CPP control). The model's mean torque is therefore
  min(Q_open water(P/D_set), Q_rated), with the thrust at the pitch that gives it.
- A **measured mean torque** never replaces this: it only identifies the pitch ratio at which the open-water
  torque equals it (`open_water.pitch_ratio_for_torque`), a number to compare with.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

from floebreak.errors import InputError, require_range
from floebreak.propeller.open_water import (
    BSeriesPropeller,
    OperatingPoint,
    TabulatedPropeller,
    operating_point,
    pitch_ratio_for_torque,
    pitch_ratio_range,
)
from floebreak.propeller.spec import PropellerSpec
from floebreak.ship.agulhas_ii import BEAM_M, BLOCK_COEFFICIENT, DRAUGHT_M, LENGTH_M

KINEMATIC_VISCOSITY_M2_S: Final = 1.19e-6  # sea water at 15 °C (ITTC 2011 fresh and sea water properties)
# the wake formula's hull form (module docstring): typical of a full-bodied twin-screw polar vessel, ASSUMED
FORM_FACTOR: Final = 1.2
CORRELATION_ALLOWANCE: Final = 0.0004


def holtrop_wake_fraction(speed_m_s: float, diameter_m: float) -> float:
    """Nominal wake fraction of a twin-screw ship (Holtrop & Mennen 1982; module docstring)."""
    require_range("ship.speed_m_s", speed_m_s, low=0.0, unit="m/s")
    reynolds = speed_m_s * LENGTH_M / KINEMATIC_VISCOSITY_M2_S
    c_f = 0.075 / (math.log10(reynolds) - 2.0) ** 2
    c_v = FORM_FACTOR * c_f + CORRELATION_ALLOWANCE
    w = (
        0.3095 * BLOCK_COEFFICIENT
        + 10.0 * c_v * BLOCK_COEFFICIENT
        - 0.23 * diameter_m / math.sqrt(BEAM_M * DRAUGHT_M)
    )
    return min(max(w, 0.0), 0.5)


def b_series(spec: PropellerSpec, pitch_ratio: float | None = None) -> BSeriesPropeller | TabulatedPropeller:
    """The spec as a B-series propeller, or on its open-water table where it has one (P/D = the spec's pitch
    over D unless `pitch_ratio` is given)."""
    ratio = spec.pitch_m / spec.diameter_m if pitch_ratio is None else pitch_ratio
    if spec.open_water_table is not None:
        return TabulatedPropeller(spec.diameter_m, ratio, spec.open_water_table)
    return BSeriesPropeller(spec.diameter_m, ratio, spec.expanded_area_ratio, int(spec.blades))


@dataclass(frozen=True)
class ControlledPoint:
    """The operating point the controller holds: the open-water point at `pitch_ratio`, the set pitch ratio,
    whether the rated torque limited it, and the wake fraction used."""

    point: OperatingPoint
    pitch_ratio: float
    set_pitch_ratio: float
    torque_limited: bool
    wake_fraction: float

    def as_dict(self) -> dict:
        p = self.point
        return {
            "wake_fraction": self.wake_fraction,
            "set_pitch_ratio": self.set_pitch_ratio,
            "pitch_ratio": self.pitch_ratio,
            "torque_limited": self.torque_limited,
            "advance_ratio": p.advance_ratio,
            "thrust_kn": p.thrust_n / 1e3,
            "mean_torque_knm": p.torque_n_m / 1e3,
            "induced_velocity_m_s": p.induced_velocity_m_s,
        }


def controlled_point(
    spec: PropellerSpec,
    speed_m_s: float,
    rated_torque_n_m: float,
    wake_fraction: float | None = None,
) -> ControlledPoint:
    """The open-water point at the spec's pitch, the pitch reduced to the rated torque where it exceeds it
    (module docstring). `wake_fraction` None: `holtrop_wake_fraction`. Out-of-range inputs raise
    InputError naming the key (propeller.wake_fraction, propeller.pitch_ratio, propeller.advance_ratio)."""
    require_range("rated_torque_n_m", rated_torque_n_m, low=0.0, unit="N m")
    w = holtrop_wake_fraction(speed_m_s, spec.diameter_m) if wake_fraction is None else wake_fraction
    require_range("propeller.wake_fraction", w, low=0.0, high=1.0, low_inclusive=True, high_inclusive=False)
    propeller = b_series(spec)
    point = operating_point(propeller, speed_m_s, w, spec.rpm)
    if point.torque_n_m <= rated_torque_n_m:
        return ControlledPoint(point, propeller.pitch_ratio, propeller.pitch_ratio, False, w)
    lowest = pitch_ratio_range(propeller)[0]
    low = operating_point(b_series(spec, lowest), speed_m_s, w, spec.rpm)
    if low.torque_n_m >= rated_torque_n_m:  # the curves' lowest pitch already exceeds it: hold that pitch
        return ControlledPoint(low, lowest, propeller.pitch_ratio, True, w)
    ratio = pitch_ratio_for_torque(rated_torque_n_m, propeller, speed_m_s, w, spec.rpm)
    limited = operating_point(b_series(spec, ratio), speed_m_s, w, spec.rpm)
    return ControlledPoint(limited, ratio, propeller.pitch_ratio, True, w)


def mean_torque_comparison(
    spec: PropellerSpec, speed_m_s: float, point: ControlledPoint, measured_knm: float | None
) -> dict:
    """The model's mean torque beside a measured one: the measured value, their ratio and the pitch ratio at
    which the open-water torque equals the measurement (None when no pitch of the fit gives it). The
    measurement never becomes the model's mean."""
    out = {"model_mean_torque_knm": point.point.torque_n_m / 1e3, "measured_mean_torque_knm": measured_knm}
    if measured_knm is None:
        return out
    require_range("mean_torque_knm", measured_knm, low=0.0, unit="kN m")
    out["measured_over_model"] = measured_knm / out["model_mean_torque_knm"]
    try:
        out["identified_pitch_ratio"] = pitch_ratio_for_torque(
            1e3 * measured_knm, b_series(spec), speed_m_s, point.wake_fraction, spec.rpm
        )
    except InputError as error:
        out["identified_pitch_ratio"] = None
        out["identification"] = str(error)
    return out


def shaft_operating_point(
    line, speed_m_s: float, measured_n_m: float | None, wake_fraction=None, open_water_table=None
):
    """The controlled point of the default propeller spec (on `open_water_table` where given) at the shaft
    `line`'s rpm, its rated torque the line's (`ShaftLine.mean_torque` without a given mean: P/(2π n)), and
    the comparison with a measured mean torque [N·m] (`mean_torque_comparison`)."""
    spec = PropellerSpec(rpm=line.rpm, open_water_table=open_water_table)
    rated = (
        float(line.rated_power_w) / (2.0 * math.pi * line.rpm / 60.0)
        if line.rated_power_w
        else line.mean_torque()
    )
    point = controlled_point(spec, speed_m_s, rated, wake_fraction)
    measured = None if measured_n_m is None else measured_n_m / 1e3
    return point, mean_torque_comparison(spec, speed_m_s, point, measured)
