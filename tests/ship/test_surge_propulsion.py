"""Ship surge (floebreak.ship.surge) against solutions derived independently in the tests: the energy
equation m·V·dV/dx = T_net(V) − F under a constant ice force, the thrust–resistance balance without ice, a
stop under a force above the bollard pull, and the force series of a hand-made contact record."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from floebreak.ship.propulsion import Propulsion, juva_riska_net_thrust_n
from floebreak.ship.surge import integrate_surge, longitudinal_ice_force_n

MASS_KG = 1.0e7
T0_N, V_MAX_M_S = 1.0e6, 8.0  # linear net thrust T_net = T0·(1 − V/V_max): a two-row table


def _linear() -> Propulsion:
    return Propulsion("table", MASS_KG, 0.0, speeds_m_s=(0.0, V_MAX_M_S), net_thrust_n=(T0_N, 0.0))


def _constant(force_n: float, length_m: float, step_m: float = 0.25):
    x = np.arange(0.0, length_m + step_m / 2, step_m)
    f = np.full(x.size, force_n)
    return x, f


def test_constant_force_speed_and_time_follow_the_energy_equation():
    # m V dV/dx = c − kV, c = T0 − F, k = T0/V_max:  x(V) = m[(V0 − V)/k + (c/k²) ln((c − kV0)/(c − kV))],
    # m dV/dt = c − kV:  t(V) = (m/k) ln((c − kV0)/(c − kV))
    force, v0 = 4.0e5, 7.0
    c, k = T0_N - force, T0_N / V_MAX_M_S
    x, f = _constant(force, 400.0)
    surge = integrate_surge(x, f, f, _linear(), v0)
    v = surge.speed_m_s
    x_expected = MASS_KG * ((v0 - v) / k + c / k**2 * np.log((c - k * v0) / (c - k * v)))
    t_expected = MASS_KG / k * np.log((c - k * v0) / (c - k * v))
    assert not surge.stuck
    assert np.abs(x_expected - surge.bow_x_m).max() < 1e-3  # metres, over 400 m
    assert surge.time_s == pytest.approx(t_expected, rel=1e-5)
    assert surge.speed_m_s[-1] < v0  # slowing towards c/k = 4.8 m/s
    assert surge.mean_ice_resistance_n == pytest.approx(
        force
    ) and surge.ice_work_per_metre_n == pytest.approx(force)


def test_without_ice_the_speed_settles_at_the_thrust_resistance_balance():
    p = Propulsion("bollard_pull", MASS_KG, 0.05, bollard_pull_n=1.2e6, open_water_speed_m_s=8.0)
    x, f = _constant(0.0, 3000.0, 1.0)
    surge = integrate_surge(x, f, f, p, 2.0)
    assert surge.speed_m_s[-1] == pytest.approx(8.0, rel=1e-3)
    assert np.all(np.diff(surge.speed_m_s) > 0.0)  # accelerating all the way, never past V_ow
    # and from above: slows down to it
    assert integrate_surge(x, f, f, p, 11.0).speed_m_s[-1] == pytest.approx(8.0, rel=1e-3)


def test_a_force_above_the_bollard_pull_stops_the_ship_where_its_energy_is_spent():
    # linear thrust, c = T0 − F < 0: x(V = 0) of the first test, x* = m[V0/k + (c/k²) ln((c − kV0)/c)]
    force, v0 = 1.5e6, 3.0
    c, k = T0_N - force, T0_N / V_MAX_M_S
    x_stop = MASS_KG * (v0 / k + c / k**2 * math.log((c - k * v0) / c))
    x, f = _constant(force, 200.0)
    surge = integrate_surge(x, f, f, _linear(), v0)
    assert surge.stuck
    assert surge.stuck_at_bow_x_m == pytest.approx(x_stop, rel=1e-6)
    assert surge.bow_x_m[-1] == surge.stuck_at_bow_x_m and surge.speed_m_s[-1] == 0.0
    # t* = (m/k) ln((c − kV0)/c)
    assert surge.time_s[-1] == pytest.approx(MASS_KG / k * math.log((c - k * v0) / c), rel=1e-4)


def test_stop_under_the_juva_riska_thrust_matches_quadrature_of_the_inverse():
    p = Propulsion("bollard_pull", MASS_KG, 0.1, bollard_pull_n=1.0e6, open_water_speed_m_s=8.0)
    force, v0, m = 1.3e6, 4.0, MASS_KG * 1.1
    # x* = ∫_0^V0 m V dV / (F − T_net(V)), by adaptive quadrature
    x_stop, _ = quad(lambda v: m * v / (force - juva_riska_net_thrust_n(v, 1.0e6, 8.0)), 0.0, v0)
    x, f = _constant(force, 500.0)
    surge = integrate_surge(x, f, f, p, v0)
    assert surge.stuck and surge.stuck_at_bow_x_m == pytest.approx(x_stop, rel=1e-5)


def test_a_short_force_peak_above_the_bollard_pull_is_crossed_on_momentum():
    # 2 MN over 1 m costs 2 MJ − T_net·1 m; the ship has ½·1e7·3² = 45 MJ
    x, f = _constant(0.0, 100.0)
    f[(x > 50.0) & (x <= 51.0)] = 2.0e6
    surge = integrate_surge(x, f, f, _linear(), 3.0)
    assert not surge.stuck and surge.speed_m_s.min() > 2.9


def test_force_series_on_arrival_and_after_the_breaks():
    # panels: normal x components 1.0 and 0.5. Step 1: floe 0 in contact (no failure), 100 N on panel 0.
    # Step 2: floe 0 (200 N on panel 0, 100 N on panel 1) breaks into pieces 1 (cusp, not evaluated) and
    # 2 (evaluated at step 2: 40 N on panel 1). Step 3: piece 2, 80 N on panel 0. Floe 3 (initial, in
    # contact at step 2, 10 N on panel 0) leaves whole (rotation) at step 2.
    step = np.array([1, 2, 2, 2, 2, 3])
    piece = np.array([0, 0, 0, 3, 2, 2])
    panel = np.array([0, 0, 1, 0, 1, 0])
    f_h = np.array([100.0, 200.0, 100.0, 10.0, 40.0, 80.0])
    failed = np.array([False, True, True, True, False, False])
    parents = np.array([-1, 0, 0, -1])
    arrival, after = longitudinal_ice_force_n(
        5, step, piece, panel, f_h, failed, parents, np.array([1.0, 0.5])
    )
    assert arrival.tolist() == [0.0, 100.0, 200.0 + 50.0 + 10.0, 80.0, 0.0]
    assert after.tolist() == [0.0, 100.0, 20.0, 80.0, 0.0]
