"""Open-water curves of the Wageningen B-series and the operating point built on them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from floebreak.errors import InputError
from floebreak.propeller.open_water import (
    KQ_TERMS,
    KT_TERMS,
    BSeriesPropeller,
    induced_velocity_m_s,
    operating_point,
    pitch_ratio_for_torque,
    thrust_coefficient,
    torque_coefficient,
    zero_thrust_advance_ratio,
)

B4_70 = BSeriesPropeller(diameter_m=1.0, pitch_ratio=1.0, area_ratio=0.70, blades=4)


def test_the_fit_has_the_published_number_of_terms():
    # Oosterveld & van Oossanen (1975), Table 1: 39 thrust and 47 torque terms
    assert len(KT_TERMS) == 39
    assert len(KQ_TERMS) == 47
    assert len({term[1:] for term in KT_TERMS}) == 39  # no exponent set twice


def test_b4_70_at_unit_pitch_matches_the_series_chart():
    # the B4-70 chart at P/D = 1.0 (Kuiper 1992, "The Wageningen propeller series", MARIN publ. 92-001):
    # K_T(0) ≈ 0.45, 10 K_Q(0) ≈ 0.68, best efficiency ≈ 0.69 near J ≈ 0.85, zero thrust near J ≈ 1.06
    assert thrust_coefficient(0.0, B4_70) == pytest.approx(0.45, abs=0.02)
    assert 10 * torque_coefficient(0.0, B4_70) == pytest.approx(0.68, abs=0.03)
    j = np.linspace(0.05, 1.0, 200)
    eta = j * thrust_coefficient(j, B4_70) / (2 * math.pi * torque_coefficient(j, B4_70))
    assert eta.max() == pytest.approx(0.69, abs=0.03)
    assert j[eta.argmax()] == pytest.approx(0.85, abs=0.07)
    assert zero_thrust_advance_ratio(B4_70) == pytest.approx(1.06, abs=0.05)


def test_more_pitch_gives_more_thrust_and_torque_at_every_advance_ratio():
    coarse = BSeriesPropeller(1.0, 1.2, 0.55, 4)
    fine = BSeriesPropeller(1.0, 0.8, 0.55, 4)
    j = np.linspace(0.0, 0.7, 15)
    assert np.all(thrust_coefficient(j, coarse) > thrust_coefficient(j, fine))
    assert np.all(torque_coefficient(j, coarse) > torque_coefficient(j, fine))
    assert np.all(np.diff(thrust_coefficient(j, coarse)) < 0)  # thrust falls as the propeller advances


def test_the_operating_point_scales_with_density_speed_and_size():
    propeller = BSeriesPropeller(4.3, 1.0, 0.55, 4)
    point = operating_point(propeller, ship_speed_m_s=3.0, wake_fraction=0.15, rpm=140.0)
    n = 140.0 / 60.0
    assert point.advance_ratio == pytest.approx(3.0 * 0.85 / (n * 4.3))
    assert point.torque_n_m == pytest.approx(point.torque_coefficient * 1025.0 * n**2 * 4.3**5)
    assert point.thrust_n == pytest.approx(point.thrust_coefficient * 1025.0 * n**2 * 4.3**4)
    # momentum theory, checked from its definition T = 2 ρ A u (V_A + u)
    area = math.pi * 4.3**2 / 4
    u = point.induced_velocity_m_s
    assert 2 * 1025.0 * area * u * (point.advance_speed_m_s + u) == pytest.approx(point.thrust_n, rel=1e-9)


def test_bollard_induced_velocity_is_the_square_root_law():
    # V_A = 0: T = 2 ρ A u² → u = √(T / (2 ρ A))
    area = math.pi * 2.0**2 / 4
    assert induced_velocity_m_s(1e5, 2.0, 0.0, 1000.0) == pytest.approx(math.sqrt(1e5 / (2 * 1000.0 * area)))


def test_a_pitch_is_identified_from_one_torque():
    propeller = BSeriesPropeller(4.3, 1.0, 0.55, 4)
    target = operating_point(propeller, 3.0, 0.15, 140.0).torque_n_m
    assert pitch_ratio_for_torque(target, propeller, 3.0, 0.15, 140.0) == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize(
    ("build", "key"),
    [
        (lambda: BSeriesPropeller(4.3, 1.6, 0.55, 4), "propeller.pitch_ratio"),
        (lambda: BSeriesPropeller(4.3, 1.0, 1.2, 4), "propeller.expanded_area_ratio"),
        (lambda: BSeriesPropeller(4.3, 1.0, 0.55, 9), "propeller.blades"),
        (
            lambda: operating_point(BSeriesPropeller(4.3, 1.0, 0.55, 4), 3.0, 1.0, 140.0),
            "propeller.wake_fraction",
        ),
        (
            lambda: operating_point(BSeriesPropeller(4.3, 0.5, 0.55, 4), 12.0, 0.0, 60.0),
            "propeller.advance_ratio",
        ),
        (
            lambda: pitch_ratio_for_torque(1e3, BSeriesPropeller(4.3, 1.0, 0.55, 4), 3.0, 0.1, 140.0),
            "mean_torque_knm",
        ),
    ],
)
def test_inputs_outside_the_curves_name_their_key(build, key):
    with pytest.raises(InputError) as error:
        build()
    assert key in str(error.value)
