"""Ice material laws against independent numbers (physics-notes §0, §3.1)."""

import numpy as np
import pytest

from floebreak.ice.material import (
    characteristic_length_by_name_m,
    characteristic_length_lu_m,
    characteristic_length_m,
    characteristic_length_scalar_m,
    flexural_rigidity_n_m,
    foundation_modulus_n_m3,
)


def test_flexural_rigidity_by_hand():
    # D = E h³ / (12 (1 − ν²)) with E = 2 GPa, ν = 0.3, h = 1 m: 2e9 / 10.92
    assert flexural_rigidity_n_m(1.0) == pytest.approx(2e9 / 10.92, rel=1e-12)


def test_foundation_modulus_is_rho_g():
    assert foundation_modulus_n_m3() == pytest.approx(1025 * 9.81)
    assert foundation_modulus_n_m3() == pytest.approx(10_055, abs=1)  # physics-notes §0


@pytest.mark.parametrize(("h", "ell"), [(0.3, 4.71), (0.6, 7.92), (1.0, 11.62), (1.2, 13.32)])
def test_characteristic_length_matches_physics_notes_table(h, ell):
    # physics-notes §1.4 table: ℓ for E = 2 GPa
    assert characteristic_length_m(h) == pytest.approx(ell, abs=0.01)


def test_characteristic_length_scales_as_h_three_quarters():
    h = np.array([0.5, 1.0, 2.0])
    ell = characteristic_length_m(h)
    assert ell / h**0.75 == pytest.approx(np.full(3, 11.62), abs=0.01)


def test_lu_form_equals_eq1_with_e_3_65_gpa():
    # physics-notes §3.1: 13.5 h^(3/4) is Eq. 1 with E ≈ 3.65 GPa
    assert characteristic_length_lu_m(1.0) == pytest.approx(13.5)
    assert characteristic_length_m(1.0, youngs_modulus_pa=3.65e9) == pytest.approx(13.5, rel=0.01)


def test_by_name():
    assert characteristic_length_by_name_m(0.8, "lu_13.5") == pytest.approx(13.5 * 0.8**0.75)
    assert characteristic_length_by_name_m(0.8, "eq1") == pytest.approx(characteristic_length_m(0.8))
    with pytest.raises(ValueError, match=r"lu_13\.5"):
        characteristic_length_by_name_m(0.8, "other")  # type: ignore[arg-type]


def test_scalar_form_is_the_array_value_for_each_model():
    for h in (0.3, 1.0, 1.7):
        assert characteristic_length_scalar_m(h) == float(characteristic_length_m(h))
        assert characteristic_length_scalar_m(h, "lu_13.5") == pytest.approx(13.5 * h**0.75, rel=1e-12)
        assert characteristic_length_scalar_m(h, "eq1", 3.65e9, 0.3, 10_000.0) == float(
            characteristic_length_m(h, 3.65e9, 0.3, 10_000.0)
        )
    assert isinstance(characteristic_length_scalar_m(1.0), float)
    assert characteristic_length_scalar_m(np.float64(0.7)) == characteristic_length_scalar_m(np.array(0.7))
    with pytest.raises(ValueError, match=r"lu_13\.5"):
        characteristic_length_scalar_m(0.8, "other")  # type: ignore[arg-type]
