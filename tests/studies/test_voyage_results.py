"""Voyage pooling: time-weighted spectra and exceedances against a hand computation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floebreak.propeller.rates import weighted_exceedance
from floebreak.propeller.ruleform import OperatingProfile, fit_rule_form
from floebreak.studies.voyage_results import (
    cusp_weights,
    period_weight,
    pooled_spectra,
    voyage_rule_form,
    weighted_counts,
)

# Two periods, hand-made:
#   A: T = 0.5 h at v = 2 m/s → D = 3600 m; n = 2 fields of L = 400 m; torques 5, 15, 15 kN·m
#   B: T = 1.0 h at v = 1 m/s → D = 3600 m; n = 1 field of L = 400 m; torque 25 kN·m
# A period's rate per hour of loads in a bin is (its cusps in the bin) / (n L) × v × 3600 s/h:
#   A, bin [10, 20): 2 / 800 m × 7200 m/h = 18 /h;   B, bin [20, 30): 1 / 400 m × 3600 m/h = 9 /h
# The voyage's rate is their time-weighted mean over T_A + T_B = 1.5 h:
#   bin [0, 10): A 1 / 800 × 7200 = 9 /h → 0.5 × 9 / 1.5 = 3 /h
#   bin [10, 20): 0.5 × 18 / 1.5 = 6 /h;   bin [20, 30): 1.0 × 9 / 1.5 = 6 /h
# Exceedances per hour: ≥ 0: 3 + 6 + 6 = 15;  ≥ 10: 12;  ≥ 20: 6.  Per km: the voyage's counts over 7.2 km.
ROWS = [
    {"duration_h": 0.5, "distance_m": 3600.0, "n_fields_complete": 2, "weight": 3600.0 / (2 * 400.0)},
    {"duration_h": 1.0, "distance_m": 3600.0, "n_fields_complete": 1, "weight": 3600.0 / (1 * 400.0)},
]
LOADS = {
    "period": np.array([0, 0, 0, 1]),
    "cases": {
        "p0": {
            "force": np.array([1.0, 2.0, 3.0, 4.0]),
            "torque": np.array([5.0, 15.0, 15.0, 25.0]),
            "beyond_table": np.zeros(4, dtype=bool),
        }
    },
}


def test_period_weight_is_distance_over_simulated_length():
    assert period_weight(3600.0, 400.0, 2) == 4.5
    assert period_weight(3600.0, 400.0, 0) == 0.0  # no field completed: the period has no loads


def test_pooled_torque_rates_are_the_time_weighted_period_rates():
    spectra = pooled_spectra(LOADS, ROWS)
    torque = spectra[("p0", "torque")]
    assert spectra["hours"] == 1.5 and spectra["distance_km"] == 7.2
    np.testing.assert_allclose(torque["edges"], [0.0, 10.0, 20.0, 30.0])
    np.testing.assert_allclose(torque["per_hour"], [3.0, 6.0, 6.0])
    np.testing.assert_allclose(torque["count"], [4.5, 9.0, 9.0])  # per hour × 1.5 h
    np.testing.assert_allclose(torque["per_km"], np.array([4.5, 9.0, 9.0]) / 7.2)
    np.testing.assert_allclose(torque["density"], np.array([4.5, 9.0, 9.0]) / (22.5 * 10.0))
    np.testing.assert_allclose(torque["exceedances"] / 1.5, [15.0, 12.0, 6.0])


def test_loads_per_propeller_are_the_cusps_share():
    # 60 % of the cusps reach a propeller, two propellers share them: 0.3 loads per cusp on one propeller
    spectra = pooled_spectra(LOADS, ROWS, share=0.6 / 2)
    np.testing.assert_allclose(spectra[("p0", "torque")]["per_hour"], np.array([3.0, 6.0, 6.0]) * 0.3)
    np.testing.assert_allclose(
        spectra[("p0", "torque")]["exceedances"] / 1.5, np.array([15.0, 12.0, 6.0]) * 0.3
    )


def test_a_period_without_fields_adds_neither_loads_nor_hours():
    rows = [*ROWS, {"duration_h": 3.0, "distance_m": 9000.0, "n_fields_complete": 0, "weight": 0.0}]
    spectra = pooled_spectra(LOADS, rows)
    assert spectra["hours"] == 1.5
    np.testing.assert_allclose(spectra[("p0", "torque")]["per_hour"], [3.0, 6.0, 6.0])


def test_weighted_counts_and_exceedances_ignore_missing_loads():
    values = np.array([1.0, np.nan, 12.0, 10.0])
    weights = np.array([2.0, 100.0, 0.5, 1.0])
    np.testing.assert_allclose(weighted_counts(values, weights, np.array([0.0, 10.0, 20.0])), [2.0, 1.5])
    assert list(weighted_exceedance(values, weights, np.array([0.0, 10.0, 10.5, 13.0]))) == pytest.approx(
        [3.5, 1.5, 0.5, 0.0]
    )


def test_voyage_rule_form_is_the_fit_of_the_sample_repeated_by_weight():
    """Period weights 4.5 and 9 (ROWS) are 1 : 2: the weighted fit equals the plain fit of period A's
    loads once and period B's twice (independent: `fit_rule_form` unweighted on the repeated sample)."""
    rng = np.random.default_rng(5)
    torque = 100.0 * rng.weibull(0.9, 30)
    loads = {
        "period": np.repeat([0, 1], [18, 12]),
        "cases": {"operated": {"force": torque / 10.0, "torque": torque, "beyond_table": np.zeros(30, bool)}},
    }
    profile = OperatingProfile(hours_in_ice_per_year=500.0, years=20.0)
    fit = voyage_rule_form(loads, cusp_weights(loads, ROWS, share=0.5), 40.0, profile)["torque_knm"]
    repeated = fit_rule_form(np.r_[torque[:18], torque[18:], torque[18:]])
    assert fit["k"] == pytest.approx(repeated.shape_k, rel=1e-9)
    assert fit["scale"] == pytest.approx(repeated.scale, rel=1e-9)
    assert fit["n_effective"] == pytest.approx((18 + 2 * 12) ** 2 / (18 + 4 * 12))
    n_life = 40.0 * 500.0 * 20.0
    assert fit["n_lifetime"] == n_life
    assert fit["x_max_lifetime"] == pytest.approx(repeated.scale * math.log(n_life) ** (1 / repeated.shape_k))
    assert fit["rule_k"] == 0.75  # open propeller (notes §7.3)
