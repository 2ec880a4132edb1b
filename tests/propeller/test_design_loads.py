"""The design-load table, checked against numbers computed by hand."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.design_loads import design_load_tables, design_loads
from floebreak.propeller.design_values import SimulatedLoads, simulated_loads
from floebreak.propeller.pipeline import analyse_cusp_loads
from floebreak.propeller.rates import RateBasis, RunExposure
from floebreak.propeller.ruleform import OperatingProfile, RuleArrangement
from floebreak.propeller.spec import PropellerSpec

# Agulhas II at PC5 with EAR 0.45 and t_0.7 = 0.08 m (as tests/propeller/test_iceclass.py), by hand:
SPEC = PropellerSpec(expanded_area_ratio=0.45, blade_thickness_07_m=0.08)
D, ND, H = 4.3, 140 / 60 * 4.3, 2.0
F_B = 23 * 1.1 * ND**0.7 * (0.45 / 4) ** 0.3 * D * H**1.4 * 1e3  # [N], branch D > 0.85 H^1.4
F_F = 250 * (0.45 / 4) * D**2 * 1e3  # [N]
Q_MAX = 202 * 0.7 * 1.15 * H**1.1 * (0.7 * 5.15 / D) ** 0.16 * (0.08 / D) ** 0.6 * ND**0.17 * D**1.9 * 1e3
# N_ice per blade of the default arrangement (two wing propellers, centreline 5.25 m deep), notes §7.4:
# f = (5.25 − 2)/(4.3/2) − 1 = 0.5116, so k2 = 0.8 − 0.4 f; k1 = 1.35 (low) or 2 (high); k3 = k4 = 1
K2 = 0.8 - 0.4 * ((5.25 - 2.0) / 2.15 - 1.0)
N_ICE = 1.35 * K2 * 11e6 * 140 / 60
N_ICE_HIGH = 2.0 * K2 * 11e6 * 140 / 60


def _table():
    return design_loads(
        SPEC,
        "PC5",
        {
            95.9: SimulatedLoads(
                max_abs_torque_n_m=420e3,
                max_abs_force_n=610e3,
                n_simulated=511,
                n_loads_profile=2.8e6,
                x_max_torque_n_m=880e3,
                x_max_force_n=1.2e6,
                fit_range_torque_n_m=(3e3, 420e3),
                blade_impacts_per_hour=400.0,
                profile_hours=25_000.0,
            ),
            0.0: SimulatedLoads(max_abs_torque_n_m=50e3, max_abs_force_n=300e3, n_simulated=511),
        },
        propeller="port",
    )


def test_rows_by_hand():
    table = _table()
    assert [row.pitch_percent for row in table.rows] == [0.0, 95.9]
    zero, full = table.rows
    assert table.rule_n_ice == pytest.approx(N_ICE, rel=1e-12)
    # with a profile: design = x_max over the profile
    assert full.design_torque_n_m == 880e3 and full.design_force_n == 1.2e6
    assert full.torque_ratio == pytest.approx(880e3 / Q_MAX, rel=1e-12)
    assert full.force_ratio == pytest.approx(1.2e6 / F_B, rel=1e-12)
    # blade impacts against N_ice, both per blade: 400/h × 25 000 h = 1e7
    assert full.blade_impacts_profile == pytest.approx(1e7)
    assert full.impacts_ratio() == pytest.approx((1e7 / N_ICE, 1e7 / N_ICE_HIGH), rel=1e-12)
    assert full.rule_cycles_per_hour() == pytest.approx((N_ICE / 25e3, N_ICE_HIGH / 25e3), rel=1e-12)
    # without: design = the largest simulated load, no impacts ratio
    assert zero.design_torque_n_m == 50e3 and zero.design_force_n == 300e3
    assert zero.torque_ratio == pytest.approx(50e3 / Q_MAX, rel=1e-12)
    assert zero.impacts_ratio() is None and zero.rule_cycles_per_hour() is None


def test_to_rows_has_units_in_every_header():
    rows = _table().to_rows()
    assert len(rows) == 2
    units = ("[%]", "[kN·m]", "[kN]", "[-]", "[1/h]")
    assert all(key == "propeller" or key.endswith(units) for key in rows[0])
    full = rows[1]
    assert full["max |Q| [kN·m]"] == pytest.approx(420.0)
    assert full["rule Q_max [kN·m]"] == pytest.approx(Q_MAX / 1e3, rel=1e-12)
    assert full["rule F_b [kN]"] == pytest.approx(F_B / 1e3, rel=1e-12)
    assert full["design F [kN]"] == pytest.approx(1200.0)
    assert full["rule N_ice per blade, k1 low [-]"] == pytest.approx(N_ICE, rel=1e-12)
    assert full["rule N_ice per blade, k1 high [-]"] == pytest.approx(N_ICE_HIGH, rel=1e-12)
    assert full["blade impacts per hour [1/h]"] == 400.0
    assert rows[0]["blade impacts over profile [-]"] is None


def test_basis_of_each_number():
    table = _table()
    zero, full = table.rows
    assert "x_max over the operating profile of N = 2.8e+06 loads" in full.basis["design Q"]
    assert "511 simulated loads" in full.basis["design Q"] and "3–420 kN·m" in full.basis["design Q"]
    assert zero.basis["design Q"].startswith("largest simulated load of 511")
    assert "UR I3" in full.basis["rule Q_max"] and "D > 1.8 H_ice" in full.basis["rule Q_max"]
    assert f"F_f = {F_F / 1e3:.4g} kN" in full.basis["rule F_b"]
    assert zero.basis["loads over profile"].startswith("not given")
    assert zero.basis["blade impacts"].startswith("not given")
    assert "wing propeller" in full.basis["rule N_ice"] and "1.35/2" in full.basis["rule N_ice"]
    basis_rows = table.basis_rows()
    assert len(basis_rows) == 2 * len(full.basis)
    assert set(basis_rows[0]) == {"propeller", "pitch [%]", "number", "basis"}


def test_as_dict_is_json_ready_in_kn():
    out = json.loads(json.dumps(_table().as_dict()))
    assert out["polar_class"] == "PC5" and out["propeller"] == "port"
    full = out["rows"][1]
    assert full["rule_max_torque_kn_m"] == pytest.approx(Q_MAX / 1e3, rel=1e-12)
    assert full["rule_forward_force_kn"] == pytest.approx(F_F / 1e3, rel=1e-12)
    assert full["impacts_ratio_low"] == pytest.approx(1e7 / N_ICE, rel=1e-12)
    assert full["rule_n_ice_high"] == pytest.approx(N_ICE_HIGH, rel=1e-12)
    assert out["rule_n_ice_inputs"]["k1_low_high"] == [1.35, 2.0]


def test_arrangement_sets_n_ice_and_bad_inputs_are_named():
    # a centre azimuthing propeller with its centreline 6.3 m deep: f = (6.3 − 2)/2.15 − 1 = 1, k2 = 0.4
    centre = RuleArrangement("centre", 6.3, "azimuthing")
    table = design_loads(SPEC, "pc5", {50.0: SimulatedLoads(1.0, 1.0)}, arrangement=centre)
    expected = 1.0 * 0.4 * 1.2 * 11e6 * 140 / 60
    assert table.rule_count.n_ice_low == pytest.approx(expected, rel=1e-12)
    assert table.rule_count.n_ice_high == pytest.approx(expected, rel=1e-12)
    with pytest.raises(InputError) as info:
        SimulatedLoads(max_abs_torque_n_m=-1.0, max_abs_force_n=1.0)
    assert info.value.field == "max_abs_torque_n_m"
    with pytest.raises(InputError) as info:
        design_loads(SPEC, "PC9", {50.0: SimulatedLoads(1.0, 1.0)})
    assert info.value.field == "polar_class"


# --- the design loads of an analysis (simulated_loads, design_load_tables) --------------------------------


def test_simulated_loads_extrapolates_a_weibull_sample_to_the_profile():
    # 20 000 loads from P(X ≥ x) = exp(−(x/λ)^k), λ = 100 kN·m, k = 0.75: the largest of N loads is
    # λ (ln N)^(1/k) (notes §7.3); N = 50 loads/h × 2 000 h = 1e5 → 100 · 11.513^(4/3) = 2 595 kN·m
    rng = np.random.default_rng(3)
    torque = 100e3 * rng.weibull(0.75, 20_000)
    force = 2.0 * torque
    sim = simulated_loads(force, torque, None, loads_per_hour=50.0, profile_hours=2_000.0)
    assert sim.n_loads_profile == pytest.approx(1e5)
    expected = 100e3 * math.log(1e5) ** (1 / 0.75)
    assert sim.x_max_torque_n_m == pytest.approx(expected, rel=0.05)
    assert sim.x_max_force_n == pytest.approx(2 * expected, rel=0.05)
    assert sim.max_abs_torque_n_m == torque.max() and sim.n_simulated == 20_000
    assert sim.fit_range_torque_n_m == (torque.min(), torque.max())


def test_simulated_loads_without_a_profile_or_a_fit_says_why():
    torque = np.array([5e3, 5e3, 5e3, math.nan])  # the NaN: a cusp that reaches no propeller
    sim = simulated_loads(torque, torque, np.array([1.0, 1.0, 0.0, 0.0]), 10.0, 100.0)
    assert sim.n_simulated == 2 and sim.max_abs_torque_n_m == 5e3 and sim.x_max_torque_n_m is None
    assert "all 2 loads are equal" in sim.no_fit_reason
    table = design_loads(SPEC, "PC5", {0.0: sim})
    assert "all 2 loads are equal" in table.rows[0].basis["design Q"]
    assert simulated_loads(torque, torque).no_fit_reason == "no operating profile or time base"


def _analysed(transport: str):
    """120 cusps of 0.5–1.6 m on the two shaft lines (y = ±5.5 m, Agulhas II arrangement), made at the stem,
    in 300 m at 3 m/s (1/36 h); PC5 over 1 000 h."""
    rng = np.random.default_rng(7)
    n = 120
    size = rng.uniform(1.0, 3.0, n)
    thickness = rng.uniform(0.5, 1.6, n)
    bow_x = np.sort(rng.uniform(0.0, 290.0, n))
    cusps = {
        "volume_m3": size**2 * thickness,
        "bbox_length_m": size,
        "bbox_width_m": size,
        "thickness_m": thickness,
        "area_m2": size**2,
        "bow_x_m": bow_x,
        "centroid_x_m": bow_x,
        "centroid_y_m": np.where(np.arange(n) % 3 == 0, -5.5, 5.5),
        "run_id": np.array(["r"] * n),
    }
    return analyse_cusp_loads(
        cusps,
        exposures={"r": RunExposure(300.0, RateBasis(3.0, None, 2))},
        transport=transport,
        polar_class="PC5",
        operating_profile=OperatingProfile(100.0, 10.0),
    )


def test_design_load_tables_per_propeller_of_the_transport():
    result = _analysed("hull")
    tables = design_load_tables(result)
    assert [t.propeller for t in tables] == ["propeller 1", "propeller 2"]
    index = result.loads["propeller_index"]
    for k, table in enumerate(tables):
        mine = index == k
        assert mine.sum() >= 10  # enough to fit the rule form
        for row in table.rows:
            amp = result.amplitudes(row.pitch_percent)
            assert row.max_abs_torque_n_m == np.nanmax(np.abs(amp.torque_nm[mine]))
            # every cusp reaching propeller k loads it once: count / (1/36 h) × 1 000 h
            assert row.n_loads_profile == pytest.approx(mine.sum() * 36.0 * 1000.0)
            assert row.rule_count.n_ice_low == pytest.approx(N_ICE)
            # blade impacts: Z·N_Q = max(1, round(4 · 2h)) per cusp on the propeller, over Z = 4 blades
            thickness = result.loads["thickness_m"][mine]
            per_blade = np.sum(np.maximum(1.0, np.rint(8.0 * thickness))) / 4.0
            assert row.blade_impacts_per_hour == pytest.approx(per_blade * 36.0)
            assert row.impacts_ratio()[1] == pytest.approx(per_blade * 36.0 * 1000.0 / N_ICE_HIGH)
            assert row.design_torque_n_m >= row.max_abs_torque_n_m  # x_max over ≥ 3e5 loads
            assert row.basis["design Q"].startswith("rule-form x_max")


def test_design_load_tables_of_the_mean_propeller_and_without_a_polar_class():
    result = _analysed("all")
    (table,) = design_load_tables(result)
    assert table.propeller == "one propeller (mean)"
    # every cusp reaches; each counts 1/2 on one propeller: 120 / 2 / (1/36 h) × 1 000 h
    assert table.rows[0].n_loads_profile == pytest.approx(120 / 2 * 36.0 * 1000.0)
    no_class = analyse_cusp_loads(_analysed_cusps_of(result), exposures=result.exposures, transport="all")
    assert design_load_tables(no_class) == []


def _analysed_cusps_of(result):
    loads = result.loads
    return {
        "volume_m3": loads["volume_m3"],
        "bbox_length_m": loads["bbox_longer_m"],
        "bbox_width_m": loads["bbox_shorter_m"],
        "thickness_m": loads["thickness_m"],
        "area_m2": loads["area_m2"],
        "run_id": loads["run_id"],
    }
