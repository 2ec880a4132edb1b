"""Nevel narrow wedge against physics-notes §1.3-1.5 tables, the beam limit and hand calculations."""

import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.mechanics import nevel

# physics-notes §1.3: ρ, S, ξ_σ (from apex), ξ_σ − ρ, m_max, ξ_M (typed in from the notes)
NOTES_TABLE_1_3 = [
    (0.0, 1.0000, 0.0, 0.0, 0.871, 1.552),
    (0.001, 0.9867, 0.114, 0.113, 0.871, 1.552),
    (0.005, 0.9617, 0.198, 0.193, 0.868, 1.555),
    (0.01, 0.9398, 0.253, 0.243, 0.865, 1.558),
    (0.02, 0.9058, 0.325, 0.305, 0.858, 1.565),
    (0.03, 0.8781, 0.377, 0.347, 0.852, 1.571),
    (0.05, 0.8324, 0.457, 0.407, 0.840, 1.585),
    (0.075, 0.7857, 0.536, 0.461, 0.826, 1.601),
    (0.10, 0.7462, 0.601, 0.501, 0.813, 1.619),
    (0.15, 0.6812, 0.711, 0.561, 0.790, 1.654),
    (0.20, 0.6287, 0.806, 0.606, 0.769, 1.690),
    (0.30, 0.5472, 0.970, 0.670, 0.735, 1.764),
    (0.50, 0.4373, 1.252, 0.752, 0.685, 1.922),
    (1.00, 0.2937, 1.857, 0.857, 0.613, 2.350),
    (2.00, 0.1782, 2.946, 0.946, 0.553, 3.273),
    (3.00, 0.1281, 3.988, 0.988, 0.526, 4.233),
]

SIGMA_F = 0.5e6  # Pa, physics-notes §1.4
E, NU, K = 2e9, 0.3, 10_055.25


def ell_by_hand(h):
    """ℓ = (D/k)^(1/4), D = E h³/(12(1 − ν²)) (thesis Eq. 1), computed independently here."""
    return (E * h**3 / (12 * (1 - NU**2)) / K) ** 0.25


def _close(value, ref, rel=0.01, abs_=1e-9):
    return value == pytest.approx(ref, rel=rel, abs=abs_)


# --------------------------------------------------------------------------------------------------
# §1.3 dimensionless table
# --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("rho", "s", "xi_s", "xi_s_edge", "m_max", "xi_m"), NOTES_TABLE_1_3)
def test_interpolated_table_reproduces_physics_notes_1_3(rho, s, xi_s, xi_s_edge, m_max, xi_m):
    assert _close(nevel.stress_factor(rho), s)
    assert _close(nevel.max_stress_distance(rho), xi_s, abs_=1e-3)
    assert _close(nevel.max_stress_distance(rho) - rho, xi_s_edge, abs_=1e-3)
    assert _close(nevel.max_moment(rho), m_max)
    assert _close(nevel.max_moment_distance(rho), xi_m)


@pytest.mark.parametrize(("rho", "s", "xi_s", "xi_s_edge", "m_max", "xi_m"), NOTES_TABLE_1_3)
def test_bvp_solution_reproduces_physics_notes_1_3(rho, s, xi_s, xi_s_edge, m_max, xi_m):
    sol = nevel.solve_wedge(rho)
    assert sol.converged
    assert _close(sol.stress_factor, s)
    assert _close(sol.max_stress_distance, xi_s, abs_=1e-3)
    assert _close(sol.max_moment, m_max)
    assert _close(sol.max_moment_distance, xi_m)


def test_solution_satisfies_boundary_conditions_and_definitions():
    sol = nevel.solve_wedge(0.2)
    assert sol.xi[0] == pytest.approx(0.2)
    assert sol.moment[0] == pytest.approx(0.0, abs=1e-8)  # M(r) = 0
    assert sol.shear[0] == pytest.approx(1.0, abs=1e-8)  # (ξW'')'(ρ) = 1
    assert sol.deflection[-1] == pytest.approx(0.0, abs=1e-8)
    np.testing.assert_allclose(sol.moment, sol.xi * sol.curvature, atol=1e-12)
    # the deflection is downward under the load and the moment hogging (u = ξW'' > 0 → M < 0)
    assert sol.deflection[0] > 0
    assert np.max(np.abs(sol.curvature)) <= sol.stress_factor * (1 + 1e-9)


def test_point_load_limit_rho_zero():
    # physics-notes §1.1: ρ → 0 gives W''(0) = 1, S(0) = 1 at the apex
    sol = nevel.solve_wedge(0.0)
    assert sol.converged
    assert sol.stress_factor == 1.0
    assert sol.max_stress_distance == 0.0
    assert sol.curvature[0] == pytest.approx(1.0, abs=1e-8)
    assert nevel.stress_factor(0.0) == 1.0
    assert nevel.max_stress_distance(0.0) == 0.0


def test_xi_sigma_grows_like_cube_root_near_apex():
    # physics-notes §1.1: ξ_σ ≈ c ρ^(1/3) for small ρ (the notes' ρ = 0.001 row gives c ≈ 1.14)
    rho = np.array([1e-4, 1e-3])
    ratio = nevel.max_stress_distance(rho) / np.cbrt(rho)
    assert ratio[0] == pytest.approx(ratio[1], rel=0.1)
    assert ratio[1] == pytest.approx(0.114 / 0.1, rel=0.01)


# --------------------------------------------------------------------------------------------------
# Semi-infinite beam limit ρ → ∞ (physics-notes §1.1 "Confidence")
# --------------------------------------------------------------------------------------------------


def test_semi_infinite_beam_limit_from_solver():
    # For ρ ≫ 1 the wedge has constant width θr: a semi-infinite beam with an end load P and M(r) = 0,
    # M(s) = −(P/β) e^(−βs) sin βs, β = 1/(√2 ℓ) → |M|max = e^(−π/4) P ℓ at s = π/(4β) = π/(2√2) ℓ.
    # Its end deflection w(r) = 2Pβ/(k θ r) is ρ W(ρ) = √2 in the wedge scaling. Corrections are O(1/ρ).
    rho = 400.0
    sol = nevel.solve_wedge(rho)
    assert sol.max_moment == pytest.approx(math.exp(-math.pi / 4), rel=2e-3)
    assert sol.max_moment_distance - rho == pytest.approx(math.pi / (2 * math.sqrt(2)), rel=2e-3)
    assert rho * sol.deflection[0] == pytest.approx(math.sqrt(2), rel=5e-3)
    assert rho * sol.stress_factor == pytest.approx(math.exp(-math.pi / 4), rel=5e-3)


def test_beam_limit_error_decays_like_one_over_rho():
    limit = math.exp(-math.pi / 4)
    err_100 = nevel.solve_wedge(100.0).max_moment - limit
    err_400 = nevel.solve_wedge(400.0).max_moment - limit
    assert err_100 > 0 and err_400 > 0
    assert err_100 / err_400 == pytest.approx(4.0, rel=0.1)


def test_table_tail_beyond_last_row_follows_beam_asymptote():
    rho_max = float(nevel.load_table()["rho"][-1])
    # continuous at the end of the table
    for func in (nevel.stress_factor, nevel.max_stress_distance, nevel.max_moment, nevel.max_moment_distance):
        assert func(rho_max * (1 + 1e-9)) == pytest.approx(func(rho_max), rel=1e-6)
    # agrees with a fresh solve beyond the table
    for rho in (80.0, 300.0):
        sol = nevel.solve_wedge(rho)
        assert nevel.stress_factor(rho) == pytest.approx(sol.stress_factor, rel=1e-3)
        assert nevel.max_stress_distance(rho) == pytest.approx(sol.max_stress_distance, rel=1e-3)
        assert nevel.max_moment(rho) == pytest.approx(sol.max_moment, rel=1e-3)
        assert nevel.max_moment_distance(rho) == pytest.approx(sol.max_moment_distance, rel=1e-3)
    assert nevel.max_moment(1e6) == pytest.approx(math.exp(-math.pi / 4), rel=1e-4)


# --------------------------------------------------------------------------------------------------
# Shipped CSV
# --------------------------------------------------------------------------------------------------


def test_shipped_csv_has_provenance_and_columns():
    from importlib.resources import files

    text = files("floebreak.data").joinpath("nevel_table.csv").read_text(encoding="utf-8")
    assert text.startswith("#")
    assert "generate_nevel_table.py" in text
    assert "solve_bvp" in text
    table = nevel.load_table()
    assert tuple(table) == nevel.TABLE_COLUMNS
    rho = table["rho"]
    assert rho[0] == 0.0 and np.all(np.diff(rho) > 0)
    assert 60 <= rho.size <= 100
    np.testing.assert_allclose(table["xi_sigma_minus_rho"], table["xi_sigma"] - rho, atol=1e-9)


def test_shipped_csv_equals_fresh_solve():
    table = nevel.load_table()
    rho = table["rho"]
    for target in (0.01, 0.3, 5.0):
        i = int(np.argmin(np.abs(rho - target)))
        sol = nevel.solve_wedge(float(rho[i]))
        assert table["stress_factor_S"][i] == pytest.approx(sol.stress_factor, rel=1e-3)
        assert table["xi_sigma"][i] == pytest.approx(sol.max_stress_distance, rel=1e-3)
        assert table["m_max"][i] == pytest.approx(sol.max_moment, rel=1e-3)
        assert table["xi_M"][i] == pytest.approx(sol.max_moment_distance, rel=1e-3)


def test_interpolation_between_grid_points_matches_fresh_solve():
    for rho in (3e-4, 0.0123, 0.37, 7.7):
        sol = nevel.solve_wedge(rho)
        assert nevel.stress_factor(rho) == pytest.approx(sol.stress_factor, rel=1e-3)
        assert nevel.max_stress_distance(rho) == pytest.approx(sol.max_stress_distance, rel=1e-3)
        assert nevel.max_moment(rho) == pytest.approx(sol.max_moment, rel=1e-3)
        assert nevel.max_moment_distance(rho) == pytest.approx(sol.max_moment_distance, rel=1e-3)


def test_table_functions_are_vectorised():
    rho = np.array([[0.0, 0.1], [1.0, 100.0]])
    for func in (nevel.stress_factor, nevel.max_stress_distance, nevel.max_moment, nevel.max_moment_distance):
        out = func(rho)
        assert out.shape == (2, 2)
        assert out[0, 1] == pytest.approx(func(0.1))
    assert isinstance(nevel.stress_factor(0.1), float)


# --------------------------------------------------------------------------------------------------
# §1.4 dimensional sanity values
# --------------------------------------------------------------------------------------------------

# h, ℓ, r, P_f(5°) kN, P_f(1 rad) kN, l_br from edge m, stress max from apex m, moment max from apex m
# (None: not given for that r in the notes)
NOTES_TABLE_1_4 = [
    (0.3, 4.71, 0.1, 0.73, 8.3, 1.5, 1.6, 7.4),
    (0.3, 4.71, 0.6, 0.92, 10.6, 2.5, 3.1, 7.7),
    (0.3, 4.71, 1.5, 1.22, 14.0, 3.2, 4.7, 8.4),
    (0.6, 7.92, 0.1, 2.8, 32, 2.1, 2.2, 12.4),
    (0.6, 7.92, 0.6, 3.3, 38, 3.7, 4.3, 12.7),
    (0.6, 7.92, 1.5, 4.1, 47, 4.7, 6.2, 13.3),
    (1.0, 11.62, 0.1, 7.7, 88, 2.7, 2.8, 18.1),
    (1.0, 11.62, 0.3, 8.2, 94, 3.9, 4.2, None),
    (1.0, 11.62, 0.6, 8.8, 101, 4.8, 5.4, None),
    (1.0, 11.62, 1.0, 9.5, 109, 5.6, 6.6, None),
    (1.0, 11.62, 1.5, 10.3, 118, 6.3, 7.8, 19.0),
    (1.2, 13.32, 0.1, 11.0, 126, 3.0, 3.1, 20.7),
    (1.2, 13.32, 0.6, 12.4, 142, 5.3, 5.9, None),
    (1.2, 13.32, 1.5, 14.4, 165, 6.9, 8.4, 21.7),
]


def _half_digit(value) -> float:
    """Half a unit of the last printed digit (the notes round), plus 1 % of the value."""
    text = repr(value)
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0**-decimals + 0.01 * abs(value)


@pytest.mark.parametrize(("h", "ell", "r", "p5_kn", "p1_kn", "l_br", "x_sigma", "x_m"), NOTES_TABLE_1_4)
def test_dimensional_values_physics_notes_1_4(h, ell, r, p5_kn, p1_kn, l_br, x_sigma, x_m):
    material = dict(youngs_modulus_pa=E, poisson_ratio=NU, foundation_modulus=K)
    assert ell_by_hand(h) == pytest.approx(ell, abs=_half_digit(ell))
    p5 = nevel.bearing_capacity_n(h, r, math.radians(5), flexural_strength_pa=SIGMA_F, **material)
    p1 = nevel.bearing_capacity_n(h, r, 1.0, flexural_strength_pa=SIGMA_F, **material)
    assert p5 / 1e3 == pytest.approx(p5_kn, abs=_half_digit(p5_kn))
    assert p1 / 1e3 == pytest.approx(p1_kn, abs=_half_digit(p1_kn))
    x_s = nevel.breaking_distance_from_apex_m(h, r, mode="max_stress", **material)
    assert x_s == pytest.approx(x_sigma, abs=_half_digit(x_sigma))
    assert x_s - r == pytest.approx(l_br, abs=_half_digit(l_br))
    if x_m is not None:
        x_mom = nevel.breaking_distance_from_apex_m(h, r, mode="max_moment", **material)
        assert x_mom == pytest.approx(x_m, abs=_half_digit(x_m))


def test_full_fan_capacity_range_physics_notes_1_4():
    # 180° fan, h = 1 m, ρ ≈ 0.03–0.1: "P ≈ 0.29–0.35 MN" (the notes round loosely: ρ = 0.03 gives
    # σ_f π h²/(6 · 0.8781) = 298 kN with S from the §1.3 table)
    ell = ell_by_hand(1.0)
    p = nevel.bearing_capacity_n(1.0, np.array([0.03, 0.1]) * ell, math.pi)
    assert p[0] == pytest.approx(SIGMA_F * math.pi / (6 * 0.8781), rel=1e-3)
    assert p[1] == pytest.approx(0.35e6, rel=0.01)
    assert np.all((p > 0.29e6) & (p < 0.36e6))


# --------------------------------------------------------------------------------------------------
# Capacity models: closed forms (physics-notes §1.4, §1.5; erratum 13)
# --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("theta_deg", [5, 30, 60, 90, 180])
def test_nevel_narrow_is_eq_1_4_with_table_stress_factor(theta_deg):
    h = 0.8
    ell = ell_by_hand(h)
    r = 0.1 * ell  # ρ = 0.1, S = 0.7462 (physics-notes §1.3)
    theta = math.radians(theta_deg)
    expected = SIGMA_F * theta * h**2 / (6 * 0.7462)
    assert nevel.bearing_capacity_n(h, r, theta) == pytest.approx(expected, rel=1e-3)


# θ, Nevel ρ = 0.026 [kN], Nevel ρ = 0.1 [kN], Kashtelyan C_f = 3 [kN] for h = 1 m (physics-notes §1.5)
NOTES_TABLE_1_5 = [
    (5, 8.2, 9.7, 1.2),
    (30, 49, 58, 42),
    (60, 98, 117, 167),
    (90, 147, 175, 375),
    (180, 294, 351, 1500),
]


@pytest.mark.parametrize(("theta_deg", "p026", "p1", "pk"), NOTES_TABLE_1_5)
def test_capacity_models_physics_notes_1_5(theta_deg, p026, p1, pk):
    ell = ell_by_hand(1.0)
    theta = math.radians(theta_deg)
    narrow = nevel.bearing_capacity_n(1.0, np.array([0.026, 0.1]) * ell, theta) / 1e3
    assert narrow[0] == pytest.approx(p026, abs=_half_digit(p026))
    assert narrow[1] == pytest.approx(p1, abs=_half_digit(p1))
    kash = nevel.bearing_capacity_n(1.0, 0.1 * ell, theta, model="kashtelyan") / 1e3
    assert kash == pytest.approx(pk, abs=_half_digit(pk))


def test_kashtelyan_closed_form():
    h, theta = np.array([0.4, 1.3]), math.radians(75)
    expected = 2.5 * (theta / math.pi) ** 2 * 0.6e6 * h**2
    got = nevel.bearing_capacity_n(
        h, 0.5, theta, model="kashtelyan", kashtelyan_coefficient=2.5, flexural_strength_pa=0.6e6
    )
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    # independent of the loading radius
    assert nevel.bearing_capacity_n(1.0, 0.1, 1.0, model="kashtelyan") == pytest.approx(
        nevel.bearing_capacity_n(1.0, 1.4, 1.0, model="kashtelyan")
    )


def test_thesis_per_wedge_uses_one_wedge_angle():
    ell = ell_by_hand(1.0)
    r = 0.1 * ell
    # one 5° wedge: σ_f φ h² / (6 S), S(0.1) = 0.7462 — independent of the fan opening
    expected = SIGMA_F * math.radians(5) * 1.0 / (6 * 0.7462)
    for theta in (math.radians(30), math.pi):
        got = nevel.bearing_capacity_n(1.0, r, theta, model="thesis_per_wedge")
        assert got == pytest.approx(expected, rel=1e-3)
    assert expected == pytest.approx(9.7e3, rel=0.01)  # physics-notes §1.5 "floes break at about 8–10 kN"
    # N_w wedges of φ carry exactly the fan capacity (narrow theory is linear in θ)
    per_wedge = nevel.bearing_capacity_n(1.0, r, math.pi, model="thesis_per_wedge")
    assert 36 * per_wedge == pytest.approx(nevel.bearing_capacity_n(1.0, r, math.pi), rel=1e-12)
    wider = nevel.bearing_capacity_n(
        1.0, r, math.pi, model="thesis_per_wedge", wedge_angle_rad=math.radians(10)
    )
    assert wider == pytest.approx(2 * per_wedge, rel=1e-12)


def test_capacity_tends_to_zero_with_thickness():
    # physics-notes §1.7 defect 3: the thesis maps h = 0 to the 0.3 m table; the capacity must vanish
    assert nevel.bearing_capacity_n(1e-4, 0.1, math.pi) < 1.0


# --------------------------------------------------------------------------------------------------
# Monotonicity
# --------------------------------------------------------------------------------------------------


def test_capacity_increases_with_thickness_and_radius():
    h = np.linspace(0.05, 3.0, 60)
    r = np.linspace(0.0, 5.0, 51)
    p = nevel.bearing_capacity_n(h[:, None], r[None, :], math.radians(90))
    assert p.shape == (60, 51)
    assert np.all(np.diff(p, axis=0) > 0)
    assert np.all(np.diff(p, axis=1) > 0)


def test_breaking_distance_increases_with_radius_and_modes_differ():
    r = np.linspace(0.0, 3.0, 31)
    x_s = nevel.breaking_distance_from_apex_m(1.0, r)
    x_m = nevel.breaking_distance_from_apex_m(1.0, r, mode="max_moment")
    assert np.all(np.diff(x_s) > 0) and np.all(np.diff(x_m) > 0)
    assert np.all(x_s >= r) and np.all(x_m > x_s)
    # erratum 11: the moment maximum lies near 1.55–1.65 ℓ for ρ ≤ 0.1
    assert x_m[0] / ell_by_hand(1.0) == pytest.approx(1.552, rel=0.01)


# --------------------------------------------------------------------------------------------------
# Bad input
# --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("h", [0.0, -0.5, float("nan"), np.array([1.0, 0.0])])
def test_nonpositive_thickness_raises(h):
    with pytest.raises(InputError, match="thickness_m"):
        nevel.bearing_capacity_n(h, 0.5, 1.0)
    with pytest.raises(InputError, match="thickness_m"):
        nevel.breaking_distance_from_apex_m(h, 0.5)


@pytest.mark.parametrize("r", [-0.1, float("inf"), np.array([0.2, -1.0])])
def test_negative_radius_raises(r):
    with pytest.raises(InputError, match="loading_radius_m"):
        nevel.bearing_capacity_n(1.0, r, 1.0)
    with pytest.raises(InputError, match="loading_radius_m"):
        nevel.breaking_distance_from_apex_m(1.0, r)


def test_other_bad_inputs_raise():
    with pytest.raises(InputError, match="rho"):
        nevel.stress_factor(-0.01)
    with pytest.raises(InputError, match="rho0"):
        nevel.solve_wedge(-1.0)
    with pytest.raises(InputError, match="opening_rad"):
        nevel.bearing_capacity_n(1.0, 0.5, 0.0)
    with pytest.raises(InputError, match="opening_rad"):
        nevel.bearing_capacity_n(1.0, 0.5, 7.0)
    with pytest.raises(InputError, match="model") as info:
        nevel.bearing_capacity_n(1.0, 0.5, 1.0, model="erceg")
    assert "nevel_narrow" in str(info.value)
    with pytest.raises(InputError, match="mode"):
        nevel.breaking_distance_from_apex_m(1.0, 0.5, mode="moment")
    with pytest.raises(InputError, match="flexural_strength_pa"):
        nevel.bearing_capacity_n(1.0, 0.5, 1.0, flexural_strength_pa=0.0)


# --------------------------------------------------------------------------------------------------
# Scalar evaluation (the bending check) against a PCHIP built here from the table, and the array functions
# --------------------------------------------------------------------------------------------------


def test_scalar_evaluation_equals_scipy_pchip_on_the_shipped_table():
    # an independent PCHIP in t = ρ^(1/3) built here from the shipped table (physics-notes §1.2 step 4)
    from scipy.interpolate import PchipInterpolator

    table = nevel.load_table()
    rho_grid = table["rho"]
    t_grid = np.cbrt(rho_grid)
    references = {
        nevel.stress_factor: PchipInterpolator(t_grid, table["stress_factor_S"]),
        nevel.max_moment: PchipInterpolator(t_grid, table["m_max"]),
    }
    offsets = {
        nevel.max_stress_distance: PchipInterpolator(t_grid, table["xi_sigma"] - rho_grid),
        nevel.max_moment_distance: PchipInterpolator(t_grid, table["xi_M"] - rho_grid),
    }
    rng = np.random.default_rng(7)
    midpoints = ((t_grid[:-1] + t_grid[1:]) / 2.0) ** 3
    rho = np.concatenate(
        [rho_grid[1:], midpoints, rng.uniform(1e-9, rho_grid[-1], 400), 10 ** rng.uniform(-9, 1.7, 400)]
    )
    rho = rho[rho <= rho_grid[-1]]
    for func, pchip in references.items():
        got = np.array([func(float(r)) for r in rho])
        np.testing.assert_allclose(got, pchip(np.cbrt(rho)), rtol=1e-12, atol=0.0)
    for func, pchip in offsets.items():
        got = np.array([func(float(r)) for r in rho])
        np.testing.assert_allclose(got, rho + pchip(np.cbrt(rho)), rtol=1e-12, atol=0.0)


def test_scalar_evaluation_equals_the_array_evaluation():
    rho = np.concatenate(
        [[0.0, 50.0, 50.5, 1e3, 1e6], np.linspace(0.0, 60.0, 601), np.geomspace(1e-9, 1, 50)]
    )
    for func in (nevel.stress_factor, nevel.max_stress_distance, nevel.max_moment, nevel.max_moment_distance):
        scalar = np.array([func(float(r)) for r in rho])
        np.testing.assert_allclose(scalar, func(rho), rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("model", nevel.CAPACITY_MODELS)
@pytest.mark.parametrize("mode", nevel.BREAKING_DISTANCE_MODES)
def test_capacity_and_breaking_distance_equals_the_two_public_functions(model, mode):
    rng = np.random.default_rng(11)
    material = dict(youngs_modulus_pa=5e9, poisson_ratio=0.33, foundation_modulus=10_055.25)
    for _ in range(200):
        h = float(rng.uniform(0.05, 4.0))
        r = float(rng.choice([0.0, rng.uniform(0.0, 2.0), rng.uniform(0.0, 800.0)]))
        theta = float(rng.uniform(1e-3, 2.0 * math.pi))
        kwargs = dict(flexural_strength_pa=0.6e6, kashtelyan_coefficient=2.5, wedge_angle_rad=0.1, **material)
        capacity, distance = nevel.capacity_and_breaking_distance(
            h, r, theta, model=model, mode=mode, **kwargs
        )
        assert capacity == pytest.approx(
            nevel.bearing_capacity_n(h, r, theta, model=model, **kwargs), rel=1e-12, abs=0.0
        )
        assert distance == pytest.approx(
            nevel.breaking_distance_from_apex_m(h, r, mode=mode, **material), rel=1e-12, abs=0.0
        )


def test_capacity_and_breaking_distance_rejects_what_the_public_functions_reject():
    with pytest.raises(InputError, match="thickness_m"):
        nevel.capacity_and_breaking_distance(0.0, 0.5, 1.0)
    with pytest.raises(InputError, match="loading_radius_m"):
        nevel.capacity_and_breaking_distance(1.0, float("nan"), 1.0)
    with pytest.raises(InputError, match="opening_rad"):
        nevel.capacity_and_breaking_distance(1.0, 0.5, 7.0)
    with pytest.raises(InputError, match="kashtelyan"):
        nevel.capacity_and_breaking_distance(1.0, 0.5, 1.0, model="other")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="max_moment"):
        nevel.capacity_and_breaking_distance(1.0, 0.5, 1.0, mode="other")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="flexural_strength_pa"):
        nevel.capacity_and_breaking_distance(1.0, 0.5, 1.0, flexural_strength_pa=-1.0)
